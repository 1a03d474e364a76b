//! What a person reads: the `Display` of a run's summaries and of a linearization, errors whose
//! `Debug` (what `fn main() -> Result<..>` prints) is their sentence without escapes, and an
//! equilibrium search that names the coordinate it cannot fix.

use lagrange::linearize::{LinearizationError, Stability};
use lagrange::prelude::*;

/// A cart (x) carrying a pendulum (θ): x is neutral (no force depends on it).
pub struct CartPole {
    pub m_cart: f64,
    pub m: f64,
    pub l: f64,
    pub g: f64,
}

#[lagrangian]
impl CartPole {
    fn lagrangian(&self, (x, x_dot): Coord, (theta, theta_dot): Coord) -> Scalar {
        let (s, c) = theta.sin_cos();
        let (vx, vy) = (x_dot + self.l * c * theta_dot, self.l * s * theta_dot);
        0.5 * self.m_cart * x_dot * x_dot
            + 0.5 * self.m * (vx * vx + vy * vy)
            + self.m * self.g * self.l * c
    }
}

const CART: CartPole = CartPole {
    m_cart: 1.0,
    m: 0.3,
    l: 0.5,
    g: 9.81,
};

#[test]
fn equilibrium_names_the_neutral_coordinate() {
    match CART.equilibrium(&[0.0, 0.1], 0.0) {
        Err(LinearizationError::NoEquilibrium { message, .. }) => {
            assert!(
                message.contains("along `x` the forces do not change"),
                "{message}"
            );
        }
        other => panic!("expected NoEquilibrium, got {other:?}"),
    }
}

#[test]
fn summaries_print_for_people() {
    let tr = Simulation::new(&CART, [0.0, 0.3], [0.2, 0.0])
        .until(2.0)
        .sample_every(0.1)
        .run()
        .unwrap();
    let stats = tr.stats.to_string();
    assert!(
        stats.ends_with(" evaluations") && stats.contains(" steps ("),
        "{stats}"
    );
    let inv = tr.invariants();
    let named = inv.named(&tr.coordinates).to_string();
    // The energy and the cart's momentum (x is cyclic) are conserved.
    assert!(
        named.starts_with("energy: ") && named.contains("\np_x: "),
        "{named}"
    );
    assert!(inv.to_string().contains("\np[0]: "), "{inv}");
    let lin = CART.linearize(&[0.0, 0.0], &[0.0, 0.0], 0.0).unwrap();
    let text = lin.to_string();
    assert!(
        text.starts_with("M δq̈ + C δq̇ + K δq = 0 with\nM = [1.3, 0.15]"),
        "{text}"
    );
    assert_eq!(lin.stability().unwrap().to_string(), "marginally stable");
    assert_eq!(
        Stability::Unstable { growth_rate: 2.0 }.to_string(),
        "unstable (growth rate 2)"
    );
}

#[test]
fn errors_debug_as_their_sentence() {
    // θ = 0 with the pendulum massless and the cart massless: M is singular.
    let weightless = CartPole {
        m_cart: 0.0,
        m: 0.0,
        ..CART
    };
    let err = Simulation::new(&weightless, [0.0, 0.3], [0.0, 0.0])
        .until(1.0)
        .run()
        .unwrap_err();
    let (debug, display) = (format!("{err:?}"), err.to_string());
    assert_eq!(debug, display);
    assert!(!debug.contains("\\u{"), "{debug}");
    let e = CART.equilibrium(&[0.0, 0.1], 0.0).unwrap_err();
    assert!(!format!("{e:?}").contains("\\u{"));
}
