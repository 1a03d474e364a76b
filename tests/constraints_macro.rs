//! `fn constraints` in `#[lagrangian]`, in both modes: the generated `impl Holonomic<N, K>`
//! (g, the constraint rows and the constrained accelerations with their multipliers) against a
//! hand-written `impl Holonomic` of the same system at random states, and the flags
//! CONSTRAINED_COORDINATES and SCLERONOMIC. A system without `fn constraints` does not
//! implement `Holonomic`.

use std::marker::PhantomData;

use lagrange::prelude::*;
use lagrange_examples::twins;

use crate::support::Rng;

const STATES: usize = 200;
const REL: f64 = 1e-12;

/// |got − want| ≤ rel · max(1, max |want|), component-wise.
fn assert_close(got: &[f64], want: &[f64], rel: f64, ctx: &str) {
    assert_eq!(got.len(), want.len(), "{ctx}");
    let scale = want.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    for (g, w) in got.iter().zip(want) {
        assert!(
            (g - w).abs() <= rel * scale,
            "{ctx}: got {got:?}, want {want:?}"
        );
    }
}

/// g, the constraint rows and the constrained accelerations and multipliers of `got` against
/// `want` at (q, q̇, t).
fn assert_same_constraints<const N: usize, const K: usize>(
    got: &impl Holonomic<N, K>,
    want: &impl Holonomic<N, K>,
    q: &[f64; N],
    v: &[f64; N],
    t: f64,
    ctx: &str,
) {
    assert_close(&got.constraints(q, t), &want.constraints(q, t), REL, ctx);
    let (g, w) = (got.constraint_rows(q, v, t), want.constraint_rows(q, v, t));
    assert_close(&g.value, &w.value, REL, ctx);
    for (gj, wj) in g.jacobian.iter().zip(&w.jacobian) {
        assert_close(gj, wj, REL, ctx);
    }
    assert_close(&g.rate, &w.rate, REL, ctx);
    assert_close(&g.curvature, &w.curvature, REL, ctx);
    let (ga, gl) = got
        .constrained_accelerations(q, v, t)
        .expect("macro constrained accelerations");
    let (wa, wl) = want
        .constrained_accelerations(q, v, t)
        .expect("hand-written constrained accelerations");
    assert_close(&ga, &wa, REL, ctx);
    assert_close(&gl, &wl, REL, ctx);
}

twins! {
    /// A spherical pendulum written in x, y, z with the rod as a constraint.
    SphericalPendulumXyz, SphericalPendulumXyzJets { m: f64, g: f64, l: f64 }
    fn lagrangian(&self, (r, r_dot): Coord3) -> Scalar {
        0.5 * self.m * r_dot.norm_squared() - self.m * self.g * r.z
    }
    /// Holonomic constraints g(q, t) = 0, one entry per constraint.
    fn constraints(&self, (r, _): Coord3) -> [Scalar; 1] {
        [r.norm_squared() - self.l * self.l]
    }
}

/// [`SphericalPendulumXyz`] written by hand.
struct SphericalHand {
    m: f64,
    g: f64,
    l: f64,
}

impl Lagrangian<3> for SphericalHand {
    const COORDINATES: [&'static str; 3] = ["r.x", "r.y", "r.z"];
    const CYCLIC: [bool; 3] = [true, true, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], v: &[S; 3], _t: S) -> S {
        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * (0.5 * self.m) - q[2] * (self.m * self.g)
    }
}

impl Holonomic<3, 1> for SphericalHand {
    fn constraints<S: Scalar>(&self, q: &[S; 3], _t: S) -> [S; 1] {
        [q[0] * q[0] + q[1] * q[1] + q[2] * q[2] - self.l * self.l]
    }
}

twins! {
    /// A plane pendulum written in x, y with the rod as a constraint.
    PlanePendulumXy, PlanePendulumXyJets { m: f64, g: f64, l: f64 }
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * self.g * y
    }
    fn constraints(&self, (x, x_dot): Coord, (y, _): Coord) -> [Scalar; 1] {
        [x * x + y * y - self.l * self.l]
    }
}

/// [`PlanePendulumXy`] written by hand.
struct PlaneHand {
    m: f64,
    g: f64,
    l: f64,
}

impl Lagrangian<2> for PlaneHand {
    const COORDINATES: [&'static str; 2] = ["x", "y"];
    const CYCLIC: [bool; 2] = [true, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
        (v[0] * v[0] + v[1] * v[1]) * (0.5 * self.m) - q[1] * (self.m * self.g)
    }
}

impl Holonomic<2, 1> for PlaneHand {
    fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] {
        [q[0] * q[0] + q[1] * q[1] - self.l * self.l]
    }
}

twins! {
    /// A particle in the vertical plane whose x is driven, x = a cos(ω t): a moving constraint
    /// that leaves y free.
    DrivenX, DrivenXJets { m: f64, g: f64, a: f64, w: f64 }
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * self.g * y
    }
    fn constraints(&self, (x, _): Coord, (_, _): Coord, t: Time) -> [Scalar; 1] {
        [x - self.a * (self.w * t).cos()]
    }
}

/// [`DrivenX`] written by hand.
struct DrivenXHand {
    m: f64,
    g: f64,
    a: f64,
    w: f64,
}

impl Lagrangian<2> for DrivenXHand {
    const COORDINATES: [&'static str; 2] = ["x", "y"];
    const CYCLIC: [bool; 2] = [true, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
        (v[0] * v[0] + v[1] * v[1]) * (0.5 * self.m) - q[1] * (self.m * self.g)
    }
}

impl Holonomic<2, 1> for DrivenXHand {
    fn constraints<S: Scalar>(&self, q: &[S; 2], t: S) -> [S; 1] {
        [q[0] - (t * self.w).cos() * self.a]
    }
}

twins! {
    /// A bead on a hoop of radius R spinning at ω about the vertical z axis, in x, y, z: two
    /// constraints, the sphere and the rotating plane of the hoop.
    HoopBead, HoopBeadJets { m: f64, g: f64, radius: f64, w: f64 }
    fn lagrangian(&self, (r, r_dot): Coord3) -> Scalar {
        0.5 * self.m * r_dot.norm_squared() - self.m * self.g * r.z
    }
    fn constraints(&self, (r, _): Coord3, t: Time) -> [Scalar; 2] {
        let (s, c) = (self.w * t).sin_cos();
        [
            r.norm_squared() - self.radius * self.radius,
            r.y * c - r.x * s,
        ]
    }
}

/// [`HoopBead`] written by hand.
struct HoopHand {
    m: f64,
    g: f64,
    radius: f64,
    w: f64,
}

impl Lagrangian<3> for HoopHand {
    const COORDINATES: [&'static str; 3] = ["r.x", "r.y", "r.z"];
    const CYCLIC: [bool; 3] = [true, true, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], v: &[S; 3], _t: S) -> S {
        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * (0.5 * self.m) - q[2] * (self.m * self.g)
    }
}

impl Holonomic<3, 2> for HoopHand {
    fn constraints<S: Scalar>(&self, q: &[S; 3], t: S) -> [S; 2] {
        let (s, c) = ((t * self.w).sin(), (t * self.w).cos());
        [
            q[0] * q[0] + q[1] * q[1] + q[2] * q[2] - self.radius * self.radius,
            q[1] * c - q[0] * s,
        ]
    }
}

twins! {
    /// [`PlanePendulumXy`] with its velocity bound and a local of the same name shadowing it:
    /// the body's `x_dot` is the local, and the velocity is never read.
    ShadowedXy, ShadowedXyJets { m: f64, g: f64, l: f64 }
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * self.g * y
    }
    fn constraints(&self, (x, x_dot): Coord, (y, _): Coord) -> [Scalar; 1] {
        let x_dot = x * x;
        [x_dot + y * y - self.l * self.l]
    }
}

twins! {
    /// A particle in the vertical plane without constraints.
    FreeXy, FreeXyJets { m: f64, g: f64 }
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * self.g * y
    }
}

#[test]
fn spherical_pendulum_in_xyz_matches_the_hand_written_constraint() {
    let mut rng = Rng(0x5eed_c0de_0000_0001);
    for k in 0..STATES {
        let (m, g, l) = (
            rng.uniform(0.5, 2.0),
            rng.uniform(1.0, 10.0),
            rng.uniform(0.5, 2.0),
        );
        let p = SphericalPendulumXyz { m, g, l };
        let hand = SphericalHand { m, g, l };
        let (q, v, t) = (
            rng.arr3(-2.0, 2.0),
            rng.arr3(-3.0, 3.0),
            rng.uniform(-5.0, 5.0),
        );
        let ctx = format!("state {k}");
        assert_same_constraints(&p, &hand, &q, &v, t, &ctx);
        assert_same_constraints(&p.jets(), &hand, &q, &v, t, &ctx);
    }
    for flags in [
        (
            <SphericalPendulumXyz as Holonomic<3, 1>>::CONSTRAINED_COORDINATES,
            <SphericalPendulumXyz as Holonomic<3, 1>>::SCLERONOMIC,
        ),
        (
            <SphericalPendulumXyzJets as Holonomic<3, 1>>::CONSTRAINED_COORDINATES,
            <SphericalPendulumXyzJets as Holonomic<3, 1>>::SCLERONOMIC,
        ),
    ] {
        assert_eq!(flags, ([true; 3], true));
    }
}

#[test]
fn plane_pendulum_in_xy_matches_the_hand_written_constraint() {
    let mut rng = Rng(0x5eed_c0de_0000_0002);
    for k in 0..STATES {
        let (m, g, l) = (
            rng.uniform(0.5, 2.0),
            rng.uniform(1.0, 10.0),
            rng.uniform(0.5, 2.0),
        );
        let p = PlanePendulumXy { m, g, l };
        let hand = PlaneHand { m, g, l };
        let q = [rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)];
        let v = [rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0)];
        let t = rng.uniform(-5.0, 5.0);
        let ctx = format!("state {k}");
        assert_same_constraints(&p, &hand, &q, &v, t, &ctx);
        assert_same_constraints(&p.jets(), &hand, &q, &v, t, &ctx);
    }
    // On the circle, at rest at the bottom moving at speed u: the centripetal acceleration u²/l.
    let p = PlanePendulumXy {
        m: 2.0,
        g: 9.81,
        l: 1.5,
    };
    for (a, _) in [
        p.constrained_accelerations(&[0.0, -1.5], &[3.0, 0.0], 0.0),
        p.jets()
            .constrained_accelerations(&[0.0, -1.5], &[3.0, 0.0], 0.0),
    ]
    .map(|r| r.expect("constrained accelerations"))
    {
        assert_close(&a, &[0.0, 9.0 / 1.5], REL, "bottom of the swing");
    }
    let shadowed = ShadowedXy {
        m: 2.0,
        g: 9.81,
        l: 1.5,
    };
    let hand = PlaneHand {
        m: 2.0,
        g: 9.81,
        l: 1.5,
    };
    let (q, v) = ([0.3, -1.2], [0.7, 0.2]);
    assert_same_constraints(&shadowed, &hand, &q, &v, 0.0, "shadowed velocity");
    assert_same_constraints(&shadowed.jets(), &hand, &q, &v, 0.0, "shadowed velocity");
    assert_eq!(
        <PlanePendulumXy as Holonomic<2, 1>>::CONSTRAINED_COORDINATES,
        [true, true]
    );
    assert_eq!(
        <PlanePendulumXyJets as Holonomic<2, 1>>::CONSTRAINED_COORDINATES,
        [true, true]
    );
    const {
        assert!(<PlanePendulumXy as Holonomic<2, 1>>::SCLERONOMIC);
        assert!(<PlanePendulumXyJets as Holonomic<2, 1>>::SCLERONOMIC);
    };
}

#[test]
fn a_moving_constraint_uses_the_time_and_is_rheonomic() {
    let mut rng = Rng(0x5eed_c0de_0000_0003);
    for k in 0..STATES {
        let (m, g, a, w) = (
            rng.uniform(0.5, 2.0),
            rng.uniform(1.0, 10.0),
            rng.uniform(0.1, 2.0),
            rng.uniform(0.1, 3.0),
        );
        let p = DrivenX { m, g, a, w };
        let hand = DrivenXHand { m, g, a, w };
        let q = [rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)];
        let v = [rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0)];
        let t = rng.uniform(-5.0, 5.0);
        let ctx = format!("driven x, state {k}");
        assert_same_constraints(&p, &hand, &q, &v, t, &ctx);
        assert_same_constraints(&p.jets(), &hand, &q, &v, t, &ctx);
        // ẍ = −a ω² cos(ω t) whatever the state; y falls freely.
        let (acc, _) = p
            .constrained_accelerations(&q, &v, t)
            .expect("constrained accelerations");
        assert_close(&acc, &[-a * w * w * (w * t).cos(), -g], 1e-11, &ctx);

        let (radius, w) = (rng.uniform(0.5, 2.0), rng.uniform(0.1, 3.0));
        let p = HoopBead { m, g, radius, w };
        let hand = HoopHand { m, g, radius, w };
        let (q, v) = (rng.arr3(-2.0, 2.0), rng.arr3(-3.0, 3.0));
        let ctx = format!("hoop, state {k}");
        assert_same_constraints(&p, &hand, &q, &v, t, &ctx);
        assert_same_constraints(&p.jets(), &hand, &q, &v, t, &ctx);
    }
    assert_eq!(
        <DrivenX as Holonomic<2, 1>>::CONSTRAINED_COORDINATES,
        [true, false]
    );
    assert_eq!(
        <DrivenXJets as Holonomic<2, 1>>::CONSTRAINED_COORDINATES,
        [true, false]
    );
    assert_eq!(
        <HoopBead as Holonomic<3, 2>>::CONSTRAINED_COORDINATES,
        [true; 3]
    );
    assert_eq!(
        <HoopBeadJets as Holonomic<3, 2>>::CONSTRAINED_COORDINATES,
        [true; 3]
    );
    const {
        assert!(!<DrivenX as Holonomic<2, 1>>::SCLERONOMIC);
        assert!(!<DrivenXJets as Holonomic<2, 1>>::SCLERONOMIC);
        assert!(!<HoopBead as Holonomic<3, 2>>::SCLERONOMIC);
        assert!(!<HoopBeadJets as Holonomic<3, 2>>::SCLERONOMIC);
        // A moving constraint does work: the energy is not conserved, in both modes (L itself is
        // autonomous), while a fixed one leaves it conserved.
        assert!(<DrivenX as Lagrangian<2>>::AUTONOMOUS);
        assert!(!<DrivenX as Lagrangian<2>>::ENERGY_CONSERVED);
        assert!(!<DrivenXJets as Lagrangian<2>>::ENERGY_CONSERVED);
        assert!(!<HoopBead as Lagrangian<3>>::ENERGY_CONSERVED);
        assert!(!<HoopBeadJets as Lagrangian<3>>::ENERGY_CONSERVED);
        assert!(<PlanePendulumXy as Lagrangian<2>>::ENERGY_CONSERVED);
        assert!(<PlanePendulumXyJets as Lagrangian<2>>::ENERGY_CONSERVED);
    };
}

/// `Probe::<T>::HOLONOMIC` is `true` when `T: Holonomic<2, 1>` or `Holonomic<2, 2>` (the
/// inherent consts win over the trait's when their bounds hold), `false` otherwise.
struct Probe<T>(PhantomData<T>);

trait NotHolonomic {
    const HOLONOMIC_1: bool = false;
    const HOLONOMIC_2: bool = false;
}

impl<T> NotHolonomic for Probe<T> {}

#[allow(dead_code)]
impl<T: Holonomic<2, 1>> Probe<T> {
    const HOLONOMIC_1: bool = true;
}

#[allow(dead_code)]
impl<T: Holonomic<2, 2>> Probe<T> {
    const HOLONOMIC_2: bool = true;
}

#[test]
fn without_fn_constraints_there_is_no_holonomic_impl() {
    const {
        assert!(Probe::<PlanePendulumXy>::HOLONOMIC_1);
        assert!(Probe::<PlanePendulumXyJets>::HOLONOMIC_1);
        assert!(!Probe::<FreeXy>::HOLONOMIC_1);
        assert!(!Probe::<FreeXyJets>::HOLONOMIC_1);
        assert!(!Probe::<FreeXy>::HOLONOMIC_2);
        assert!(!Probe::<FreeXyJets>::HOLONOMIC_2);
    };
    // Nothing else changes for it.
    let p = FreeXy { m: 2.0, g: 9.81 };
    let a = p
        .accelerations(&[1.0, 2.0], &[3.0, 4.0], 0.0)
        .expect("accelerations");
    assert_close(&a, &[0.0, -9.81], REL, "free fall");
    assert_eq!(<FreeXy as Lagrangian<2>>::CYCLIC, [true, false]);
}

/// `linearize` of a system whose `#[lagrangian]` declares constraints refuses (both modes): the
/// unconstrained L's linearization has modes the rod forbids (here a free fall along the rod),
/// which it used to return as `Ok`. The hand-written twin, which does not say it is constrained,
/// still linearizes its unconstrained L.
#[test]
fn linearize_refuses_a_constrained_system() {
    let sym = SphericalPendulumXyz {
        m: 1.0,
        g: 9.81,
        l: 2.0,
    };
    let (q, v) = ([0.0, 0.0, -2.0], [0.0; 3]);
    for r in [
        sym.linearize(&q, &v, 0.0),
        sym.jets().linearize(&q, &v, 0.0),
    ] {
        match r {
            Err(DynamicsError::Constrained { message, .. }) => {
                assert!(message.contains("linearize_on_constraints"), "{message}");
            }
            other => panic!(
                "expected a refusal, got {:?}",
                other.map(|l| l.eigenvalues())
            ),
        }
    }
    const { assert!(<SphericalPendulumXyz as Lagrangian<3>>::COMPILED.constrained) };
    // The method it names: on the sphere at the bottom, in x and y, ω² = g/l in both modes.
    for lin in [
        sym.linearize_on_constraints(&q, &v, 0.0),
        sym.jets().linearize_on_constraints(&q, &v, 0.0),
    ] {
        let r = lin.unwrap().reduce(["r.x", "r.y"]).unwrap();
        for i in 0..2 {
            assert!(
                (r.k[(i, i)] / r.m[(i, i)] - 9.81 / 2.0).abs() < 1e-12,
                "{r:?}"
            );
        }
        assert!(r.is_stable());
    }
    let hand = SphericalHand {
        m: 1.0,
        g: 9.81,
        l: 2.0,
    };
    assert!(hand.linearize(&q, &v, 0.0).is_ok());
}

twins! {
    /// A Chaplygin sleigh: mass m, inertia i about its centre (x, y), heading φ, on a blade a
    /// behind the centre that does not slide sideways. No coordinate is in L.
    SleighXy, SleighXyJets { m: f64, i: f64, a: f64 }
    fn lagrangian(&self, (_x, x_dot): Coord, (_y, y_dot): Coord, (_phi, phi_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) + 0.5 * self.i * phi_dot * phi_dot
    }
    fn velocity_constraints(&self, (_, x_dot): Coord, (_, y_dot): Coord, (phi, phi_dot): Coord) -> [Scalar; 1] {
        [y_dot * phi.cos() - x_dot * phi.sin() - self.a * phi_dot]
    }
}

twins! {
    /// A bead on the vertical line x = c, free along y and in z: the constraint reads x only.
    BeadOnLine, BeadOnLineJets { m: f64, c: f64 }
    fn lagrangian(&self, (_x, x_dot): Coord, (_y, y_dot): Coord, (_z, z_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot + z_dot * z_dot)
    }
    fn constraints(&self, (x, _): Coord, (_y, _): Coord, (_z, _): Coord) -> [Scalar; 1] {
        [x - self.c]
    }
}

/// The flags are those of the constrained motion: a coordinate the constraints read is neither
/// cyclic nor has a conserved momentum (the sleigh's blade pushes on x, y and φ, none of them in
/// its L: its momenta change, as the run shows), and a coordinate no constraint reads keeps
/// what L gives it (the bead's y and z).
#[test]
fn flags_are_those_of_the_constrained_motion() {
    assert_eq!(<SleighXy as Lagrangian<3>>::CYCLIC, [false; 3]);
    assert_eq!(<SleighXyJets as Lagrangian<3>>::CYCLIC, [false; 3]);
    assert_eq!(<SleighXy as Lagrangian<3>>::MOMENTUM_CONSERVED, [false; 3]);
    assert_eq!(
        <SleighXyJets as Lagrangian<3>>::MOMENTUM_CONSERVED,
        [false; 3]
    );
    const { assert!(<SleighXy as Lagrangian<3>>::ENERGY_CONSERVED) };
    assert_eq!(<BeadOnLine as Lagrangian<3>>::CYCLIC, [false, true, true]);
    assert_eq!(
        <BeadOnLineJets as Lagrangian<3>>::CYCLIC,
        [false, true, true]
    );
    assert_eq!(
        <BeadOnLine as Lagrangian<3>>::MOMENTUM_CONSERVED,
        [false, true, true]
    );
    // The sleigh's momentum p_x = m ẋ changes along its run (the flag is not a convention).
    let s = SleighXy {
        m: 2.0,
        i: 0.3,
        a: 0.4,
    };
    let tr = Simulation::new(&s, [0.0; 3], [0.2, 0.6, 1.5])
        .until(2.0)
        .run()
        .unwrap();
    let px = |k: usize| s.momenta(&tr.q[k], &tr.qdot[k], tr.t[k])[0];
    assert!((px(tr.t.len() - 1) - px(0)).abs() > 0.1);
    assert!(tr.invariants().momenta.iter().all(|m| m.is_none()));
}

/// `EQUATIONS` of a constrained system shows the constraint forces on each coordinate it acts
/// on and the constraints themselves: the bead's x line carries λ·∂g/∂x, its y and z lines
/// nothing; the sleigh's three lines carry λ·∂c/∂q̇ and its constraint follows.
#[test]
fn equations_show_the_constraint_forces_and_the_constraints() {
    let bead = BeadOnLine::EQUATIONS;
    let lines: Vec<&str> = bead.lines().collect();
    assert_eq!(lines.len(), 4, "{bead}");
    assert!(
        lines[0].starts_with("x: ") && lines[0].ends_with(" + λ·∂g/∂x"),
        "{bead}"
    );
    assert!(!lines[1].contains('λ') && !lines[2].contains('λ'), "{bead}");
    assert_eq!(
        lines[3],
        "with g(q, t) = [x - c] = 0 (fn constraints; λ its multipliers)"
    );
    let sleigh = SleighXy::EQUATIONS;
    let lines: Vec<&str> = sleigh.lines().collect();
    assert_eq!(lines.len(), 4, "{sleigh}");
    for (line, name) in lines.iter().zip(["x", "y", "phi"]) {
        assert!(
            line.contains(&format!(" + λ·∂c/∂{name}\u{307}")),
            "{sleigh}"
        );
    }
    assert!(
        lines[3].starts_with(
            "with c(q, q̇, t) = [y_dot * phi.cos() - x_dot * phi.sin() - a * phi_dot] = 0"
        ),
        "{sleigh}"
    );
    let latex = BeadOnLine::EQUATIONS_LATEX;
    assert!(
        latex
            .lines()
            .next()
            .unwrap()
            .ends_with(" + \\lambda \\cdot \\partial g / \\partial q_{0}"),
        "{latex}"
    );
    assert!(
        latex.ends_with("\\text{with } g(q, t) = [\\texttt{x - c}] = 0"),
        "{latex}"
    );
}
