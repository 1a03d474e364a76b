//! The examples' animations as the tests check them: each system's run (shorter than the
//! example's), its [`Animation`], and the run's own scene at each of its samples, to compare the
//! written file and the page against.

use lagrange::animation::{Animation, AnimationError};
use lagrange::prelude::*;
use lagrange::scene::Visual;

use crate::bicycle_system::Bicycle;
use crate::contact_systems::{Block, RimlessWheel};
use crate::double_pendulum_system::DoublePendulum;
use crate::four_bar_system::FourBar;
use crate::heavy_top_system::HeavyTop;

/// A run made into an animation, with the run's own scene at its samples and jumps.
pub struct Watched {
    /// The example's name (`heavy_top`, …).
    pub name: &'static str,
    /// The animation (the default bound on keyframes).
    pub animation: Animation,
    /// The scene of the run's state at time `t`: a sample's, or the state before a jump at `t`
    /// (`None` if the run has no state recorded there).
    pub scene_at: Box<dyn Fn(f64) -> Option<Scene>>,
    /// The number of samples of the run.
    pub samples: usize,
    /// The times of the run's jumps.
    pub jumps: Vec<f64>,
}

fn watched<V: Visual<N> + 'static, const N: usize>(
    name: &'static str,
    sys: V,
    traj: Trajectory<N>,
) -> Result<Watched, AnimationError> {
    let animation = Animation::of(&traj, &sys).title(name).build()?;
    let samples = traj.t.len();
    let jumps = traj.jumps.iter().map(|j| j.t).collect();
    let scene_at = Box::new(move |t: f64| {
        let q = traj
            .jumps
            .iter()
            .find(|j| j.t == t)
            .map(|j| j.before.0)
            .or_else(|| traj.t.iter().position(|&s| s == t).map(|k| traj.q[k]))?;
        Some(sys.scene(&q, t))
    });
    Ok(Watched {
        name,
        animation,
        scene_at,
        samples,
        jumps,
    })
}

/// The examples' systems, each run for a few seconds and animated: the heavy top, the bicycle
/// at 5 m/s, the rocking block, the rimless wheel, the double pendulum and the four-bar linkage.
///
/// ```
/// let all = lagrange_examples::animations::all().unwrap();
/// assert_eq!(all.len(), 6);
/// ```
pub fn all() -> Result<Vec<Watched>, Box<dyn std::error::Error>> {
    let top = HeavyTop {
        i_perp: 1.0,
        i_par: 0.6,
        mgl: 1.0,
    };
    let top_run = Simulation::new(&top, [1.0, 0.0, 0.0], [0.0, -0.5, 8.0])
        .until(6.0)
        .sample_every(0.01)
        .run()?;
    let bike = Bicycle::benchmark();
    let bike_run = bike.watch(5.0, 2.0)?;
    let block = Block {
        m: 3.0,
        g: 9.81,
        b: 0.2,
        h: 0.6,
    };
    let (b, h, th0): (f64, f64, f64) = (0.2, 0.6, 0.2);
    let block_run = Simulation::new(
        &block,
        [
            b * th0.cos() - h * th0.sin(),
            b * th0.sin() + h * th0.cos(),
            th0,
        ],
        [0.0; 3],
    )
    .until(2.5)
    .sample_every(0.005)
    .run()?;
    let wheel = RimlessWheel {
        m: 2.0,
        g: 9.81,
        l: 1.0,
        slope: 0.08,
    };
    let alpha = std::f64::consts::PI / crate::contact_systems::SPOKES as f64;
    let w0 = 1.2 * crate::contact_systems::omega_star(&wheel);
    let wheel_run = Simulation::new(
        &wheel,
        [-alpha.sin(), alpha.cos(), alpha],
        [w0 * alpha.cos(), w0 * alpha.sin(), -w0],
    )
    .until(6.0)
    .sample_every(0.01)
    .run()?;
    let pendulum = DoublePendulum {
        m1: 1.0,
        m2: 1.0,
        l1: 1.0,
        l2: 1.0,
        g: 9.81,
    };
    let pendulum_run = Simulation::new(&pendulum, [2.0, -1.0], [0.0, 3.0])
        .until(6.0)
        .sample_every(0.01)
        .run()?;
    let four_bar = FourBar::crank_rocker();
    let (q0, v0) = four_bar.closed_state(0.0, std::f64::consts::TAU);
    let four_bar_run = Simulation::new(&four_bar, q0, v0)
        .until(4.0)
        .sample_every(0.01)
        .run()?;
    Ok(vec![
        watched("heavy_top", top, top_run)?,
        watched("bicycle", bike, bike_run)?,
        watched("rocking_block", block, block_run)?,
        watched("rimless_wheel", wheel, wheel_run)?,
        watched("double_pendulum", pendulum, pendulum_run)?,
        watched("four_bar", four_bar, four_bar_run)?,
    ])
}
