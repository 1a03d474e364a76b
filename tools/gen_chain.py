#!/usr/bin/env python3
"""Writes out the Lagrangian of an N-link planar pendulum chain (equal links, masses m, lengths l)
as a `#[lagrangian]` declaration, for tests/symbolic.rs and benches/symbolic.rs.

Usage: tools/gen_chain.py N SymName JetName   (prints Rust to stdout)
"""
import sys


def chain(n, sym, jet):
    params = ", ".join(f"(th{k}, th{k}_dot): Coord" for k in range(1, n + 1))
    body = []
    for k in range(1, n + 1):
        body.append(f"let (s{k}, c{k}) = th{k}.sin_cos();")
        if k == 1:
            body.append(f"let mut vx = self.l * c{k} * th{k}_dot;")
            body.append(f"let mut vy = self.l * s{k} * th{k}_dot;")
            body.append(f"let mut y = -self.l * c{k};")
            body.append("let mut lag = 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;")
        else:
            body.append(f"vx += self.l * c{k} * th{k}_dot;")
            body.append(f"vy += self.l * s{k} * th{k}_dot;")
            body.append(f"y -= self.l * c{k};")
            body.append("lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;")
    body.append("lag")
    b = "\n        ".join(body)
    out = []
    for name, attr in [(sym, "#[lagrangian]"), (jet, '#[lagrangian(mode = "jets")]')]:
        out.append(f"""/// A {n}-link pendulum chain (equal masses and lengths), L written out.
#[derive(Debug, Clone, Copy)]
pub struct {name} {{
    pub m: f64,
    pub l: f64,
    pub g: f64,
}}

{attr}
impl {name} {{
    #[allow(clippy::too_many_arguments)]
    fn lagrangian(&self, {params}) -> Scalar {{
        {b}
    }}
}}
""")
    return "\n".join(out)


if __name__ == "__main__":
    print(chain(int(sys.argv[1]), sys.argv[2], sys.argv[3]))
