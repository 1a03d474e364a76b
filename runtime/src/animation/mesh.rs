//! Triangle meshes of the shapes, in each shape's own frame (the z axis a cylinder's or a
//! disc's axis): positions, normals and indices for the glTF buffer.

use std::f64::consts::PI;

use crate::scene::Geometry;

/// A mesh: vertex positions and normals, and triangles as indices.
#[derive(Default)]
pub(crate) struct Mesh {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub indices: Vec<u16>,
}

impl Mesh {
    fn vertex(&mut self, p: [f64; 3], n: [f64; 3]) -> u16 {
        self.positions.push(p.map(|x| x as f32));
        self.normals.push(n.map(|x| x as f32));
        (self.positions.len() - 1) as u16
    }
}

/// The mesh of a shape's geometry (`None` for a trace, which is a line).
pub(crate) fn of(g: &Geometry) -> Option<Mesh> {
    match *g {
        Geometry::Sphere { radius } => Some(sphere(radius)),
        Geometry::Cylinder { radius, length } => Some(cylinder(radius, length, 24)),
        Geometry::Disc { radius, thickness } => Some(cylinder(radius, thickness, 48)),
        Geometry::Cuboid { size } => Some(cuboid(size)),
        Geometry::Trace => None,
    }
}

fn sphere(r: f64) -> Mesh {
    let (rings, segments) = (16, 32);
    let mut m = Mesh::default();
    for i in 0..=rings {
        let theta = PI * i as f64 / rings as f64;
        for j in 0..=segments {
            let phi = 2.0 * PI * j as f64 / segments as f64;
            let n = [
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ];
            m.vertex(n.map(|x| r * x), n);
        }
    }
    let row = segments + 1;
    for i in 0..rings {
        for j in 0..segments {
            let a = (i * row + j) as u16;
            let b = a + row as u16;
            m.indices.extend_from_slice(&[a, b, a + 1, a + 1, b, b + 1]);
        }
    }
    m
}

fn cylinder(r: f64, length: f64, segments: usize) -> Mesh {
    let h = length / 2.0;
    let mut m = Mesh::default();
    // The side: a ring at each end, radial normals.
    for j in 0..=segments {
        let phi = 2.0 * PI * j as f64 / segments as f64;
        let (s, c) = phi.sin_cos();
        m.vertex([r * c, r * s, -h], [c, s, 0.0]);
        m.vertex([r * c, r * s, h], [c, s, 0.0]);
    }
    for j in 0..segments as u16 {
        let a = 2 * j;
        m.indices
            .extend_from_slice(&[a, a + 2, a + 1, a + 1, a + 2, a + 3]);
    }
    // The caps: a fan about each centre.
    for (z, nz) in [(-h, -1.0), (h, 1.0)] {
        let centre = m.vertex([0.0, 0.0, z], [0.0, 0.0, nz]);
        let first = m.positions.len() as u16;
        for j in 0..=segments {
            let phi = 2.0 * PI * j as f64 / segments as f64;
            m.vertex([r * phi.cos(), r * phi.sin(), z], [0.0, 0.0, nz]);
        }
        for j in 0..segments as u16 {
            let (a, b) = (first + j, first + j + 1);
            if nz > 0.0 {
                m.indices.extend_from_slice(&[centre, a, b]);
            } else {
                m.indices.extend_from_slice(&[centre, b, a]);
            }
        }
    }
    m
}

fn cuboid(size: [f64; 3]) -> Mesh {
    let h = size.map(|x| x / 2.0);
    let mut m = Mesh::default();
    // One face per axis and sign: its normal n, and two axes u, v with u × v = n.
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let (u, v) = if sign > 0.0 { (u, v) } else { (v, u) };
            let mut n = [0.0; 3];
            n[axis] = sign;
            let first = m.positions.len() as u16;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let mut p = [0.0; 3];
                p[axis] = sign * h[axis];
                p[u] = a * h[u];
                p[v] = b * h[v];
                m.vertex(p, n);
            }
            m.indices.extend_from_slice(&[
                first,
                first + 1,
                first + 2,
                first,
                first + 2,
                first + 3,
            ]);
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle faces outwards: its normal (by the winding) along the vertices' normals.
    #[test]
    fn triangles_face_outwards() {
        for g in [
            Geometry::Sphere { radius: 1.0 },
            Geometry::Cylinder {
                radius: 0.5,
                length: 2.0,
            },
            Geometry::Cuboid {
                size: [1.0, 2.0, 3.0],
            },
        ] {
            let m = of(&g).expect("a mesh");
            for tri in m.indices.chunks(3) {
                let at =
                    |k: usize| nalgebra::Vector3::from(m.positions[tri[k] as usize].map(f64::from));
                let p = [at(0), at(1), at(2)];
                let n = (p[1] - p[0]).cross(&(p[2] - p[0]));
                let avg: nalgebra::Vector3<f64> = tri
                    .iter()
                    .map(|&i| nalgebra::Vector3::from(m.normals[i as usize].map(f64::from)))
                    .sum();
                // Degenerate triangles at the sphere's poles have no winding.
                if n.norm() > 1e-9 {
                    assert!(n.dot(&avg) > 0.0, "{g:?}: a triangle faces inwards");
                }
            }
        }
    }
}
