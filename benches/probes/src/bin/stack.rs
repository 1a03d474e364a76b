//! Where the jets path's stack use crosses 2 MiB: a hand-written chain of N coordinates,
//! one operation per run (accelerations, linearize, a DOP853 run), on threads of given stacks.
use lagrange::prelude::*;

#[derive(Clone, Copy)]
struct Chain<const N: usize>;
impl<const N: usize> Lagrangian<N> for Chain<N> {
    const COORDINATES: [&'static str; N] = ["q"; N];
    const CYCLIC: [bool; N] = [false; N];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; N], v: &[S; N], _t: S) -> S {
        let mut lag = S::constant(0.0);
        for k in 0..N {
            lag += v[k] * v[k] * 0.5 - q[k] * q[k];
        }
        for k in 1..N {
            let d = q[k] - q[k - 1];
            lag -= d * d * 0.5;
        }
        lag
    }
}

fn op<const N: usize>(which: &str) -> String {
    let q: [f64; N] = core::array::from_fn(|i| 0.01 * i as f64);
    match which {
        "acc" => format!("{:?}", Chain::<N>.accelerations(&q, &[0.0; N], 0.0).map(|a| a[0])),
        "lin" => format!("{:?}", Chain::<N>.linearize(&q, &[0.0; N], 0.0).map(|l| l.k[(0, 0)])),
        "run" => format!("{:?}", Simulation::new(&Chain::<N>, q, [0.0; N]).until(0.01).run().map(|t| t.q.len())),
        _ => unreachable!(),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (n, which, mib): (usize, String, usize) = (args[1].parse().unwrap(), args[2].clone(), args[3].parse().unwrap());
    let w = which.clone();
    let h = std::thread::Builder::new().stack_size(mib << 20).spawn(move || match n {
        8 => op::<8>(&w),
        16 => op::<16>(&w),
        24 => op::<24>(&w),
        32 => op::<32>(&w),
        48 => op::<48>(&w),
        64 => op::<64>(&w),
        _ => unreachable!(),
    }).unwrap();
    println!("N={n} {which} stack {mib} MiB: {}", h.join().unwrap());
}
