//! What a run looks like: a [`Scene`] of shapes placed in space from the coordinates, declared
//! next to the Lagrangian (`fn scene` in a `#[lagrangian]` block, or [`Visual`] by hand), and
//! written out of a run as a glTF 2.0 animation or a web page that plays it
//! ([`Trajectory::write_gltf`](crate::Trajectory::write_gltf),
//! [`Trajectory::write_html`](crate::Trajectory::write_html)).
//!
//! ```
//! use lagrange_runtime::geometry::Rotation;
//! use lagrange_runtime::scene::{Rgb, Scene};
//! use lagrange_runtime::Vector3;
//! let theta = 0.3_f64;
//! let bob = Rotation::about_z(theta) * Vector3::new(0.0, -1.0, 0.0);
//! let scene = Scene::new()
//!     .up(Vector3::y())
//!     .rod("rod", Vector3::zeros(), bob, 0.02, Rgb::GREY)
//!     .sphere("bob", bob, 0.1, Rgb::ORANGE)
//!     .trace("path", bob, Rgb::RED);
//! assert_eq!(scene.shapes.len(), 3);
//! assert_eq!(scene.shapes[1].position, bob);
//! ```

use crate::Vector3;
use crate::geometry::Rotation;
use nalgebra::Matrix3;

/// A colour: red, green and blue in 0 … 1 (sRGB, as colour pickers give them).
///
/// ```
/// use lagrange_runtime::scene::Rgb;
/// assert_eq!(Rgb::new(1.0, 0.5, 0.0).g, 0.5);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rgb {
    /// Red, 0 … 1.
    pub r: f64,
    /// Green, 0 … 1.
    pub g: f64,
    /// Blue, 0 … 1.
    pub b: f64,
}

impl Rgb {
    /// A colour from its red, green and blue, each 0 … 1.
    ///
    /// ```
    /// use lagrange_runtime::scene::Rgb;
    /// assert_eq!(Rgb::new(0.0, 0.0, 1.0), Rgb::BLUE);
    /// ```
    pub const fn new(r: f64, g: f64, b: f64) -> Self {
        Rgb { r, g, b }
    }
    /// Red.
    pub const RED: Rgb = Rgb::new(0.85, 0.15, 0.12);
    /// Green.
    pub const GREEN: Rgb = Rgb::new(0.2, 0.65, 0.25);
    /// Blue.
    pub const BLUE: Rgb = Rgb::new(0.0, 0.0, 1.0);
    /// Orange.
    pub const ORANGE: Rgb = Rgb::new(0.95, 0.55, 0.1);
    /// Yellow.
    pub const YELLOW: Rgb = Rgb::new(0.95, 0.85, 0.2);
    /// Purple.
    pub const PURPLE: Rgb = Rgb::new(0.55, 0.3, 0.75);
    /// Grey.
    pub const GREY: Rgb = Rgb::new(0.55, 0.55, 0.58);
    /// Near black.
    pub const BLACK: Rgb = Rgb::new(0.08, 0.08, 0.08);
    /// White.
    pub const WHITE: Rgb = Rgb::new(1.0, 1.0, 1.0);
    /// Steel blue.
    pub const STEEL: Rgb = Rgb::new(0.27, 0.51, 0.71);
}

/// What a shape is and its sizes (metres, or the model's length unit). Each is drawn in its own
/// frame, [`Shape::rotation`] about [`Shape::position`].
///
/// ```
/// use lagrange_runtime::scene::Geometry;
/// let g = Geometry::Cylinder { radius: 0.1, length: 2.0 };
/// assert_eq!(g.kind(), "cylinder");
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Geometry {
    /// A ball about its centre.
    Sphere {
        /// Radius.
        radius: f64,
    },
    /// A cylinder along its frame's z axis, centred on its position (a rod between two
    /// points is one).
    Cylinder {
        /// Radius.
        radius: f64,
        /// Length along z.
        length: f64,
    },
    /// A box centred on its position, its edges along its frame's axes.
    Cuboid {
        /// The full lengths along x, y and z.
        size: [f64; 3],
    },
    /// A flat disc (a wheel) centred on its position, its axis its frame's z axis.
    Disc {
        /// Radius.
        radius: f64,
        /// Thickness along z.
        thickness: f64,
    },
    /// A line through every position a point takes during the run: its trace.
    Trace,
}

impl Geometry {
    /// The kind's name (`"sphere"`, `"cylinder"`, `"cuboid"`, `"disc"`, `"trace"`).
    ///
    /// ```
    /// assert_eq!(lagrange_runtime::scene::Geometry::Trace.kind(), "trace");
    /// ```
    pub fn kind(&self) -> &'static str {
        match self {
            Geometry::Sphere { .. } => "sphere",
            Geometry::Cylinder { .. } => "cylinder",
            Geometry::Cuboid { .. } => "cuboid",
            Geometry::Disc { .. } => "disc",
            Geometry::Trace => "trace",
        }
    }

    /// The sizes, named, in the order they are declared (for checks and messages).
    ///
    /// ```
    /// use lagrange_runtime::scene::Geometry;
    /// assert_eq!(Geometry::Sphere { radius: 2.0 }.sizes(), vec![("radius", 2.0)]);
    /// ```
    pub fn sizes(&self) -> Vec<(&'static str, f64)> {
        match *self {
            Geometry::Sphere { radius } => vec![("radius", radius)],
            Geometry::Cylinder { radius, length } => vec![("radius", radius), ("length", length)],
            Geometry::Cuboid { size } => {
                vec![
                    ("size x", size[0]),
                    ("size y", size[1]),
                    ("size z", size[2]),
                ]
            }
            Geometry::Disc { radius, thickness } => {
                vec![("radius", radius), ("thickness", thickness)]
            }
            Geometry::Trace => Vec::new(),
        }
    }

    /// The radius of a ball about the shape's position that holds it.
    ///
    /// ```
    /// use lagrange_runtime::scene::Geometry;
    /// assert_eq!(Geometry::Cuboid { size: [2.0, 2.0, 1.0] }.extent(), 1.5);
    /// ```
    pub fn extent(&self) -> f64 {
        match *self {
            Geometry::Sphere { radius } => radius,
            Geometry::Cylinder { radius, length } => radius.hypot(length / 2.0),
            Geometry::Cuboid { size } => {
                0.5 * (size[0] * size[0] + size[1] * size[1] + size[2] * size[2]).sqrt()
            }
            Geometry::Disc { radius, thickness } => radius.hypot(thickness / 2.0),
            Geometry::Trace => 0.0,
        }
    }
}

/// One shape of a scene: its name, what it is, where it is and how it is turned, its colour.
///
/// ```
/// use lagrange_runtime::scene::{Rgb, Scene};
/// use lagrange_runtime::Vector3;
/// let s = Scene::new().sphere("bob", Vector3::new(1.0, 0.0, 0.0), 0.1, Rgb::RED);
/// assert_eq!(s.shapes[0].name, "bob");
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Shape {
    /// Its name (the glTF node's; unique in the scene).
    pub name: String,
    /// What it is and its sizes.
    pub geometry: Geometry,
    /// Where its centre is (for a trace: the point traced).
    pub position: Vector3<f64>,
    /// Its frame's orientation: the columns are its x, y and z axes in space.
    pub rotation: Matrix3<f64>,
    /// Its colour.
    pub color: Rgb,
}

/// Shapes placed in space: what [`Visual::scene`] returns at each state of a run.
///
/// ```
/// use lagrange_runtime::scene::{Rgb, Scene};
/// use lagrange_runtime::Vector3;
/// let s = Scene::new().cuboid("floor", lagrange_runtime::geometry::Rotation::identity(),
///     Vector3::new(0.0, 0.0, -0.05), Vector3::new(4.0, 4.0, 0.1), Rgb::GREY);
/// assert_eq!(s.up, Vector3::z());
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The shapes, in the order they were added.
    pub shapes: Vec<Shape>,
    /// The direction that is up in the model's coordinates (z unless [`Scene::up`] says
    /// otherwise): the viewer shows it up.
    pub up: Vector3<f64>,
}

impl Default for Scene {
    fn default() -> Self {
        Scene::new()
    }
}

/// The rotation that takes the z axis to the direction of `d` (the identity for d = 0).
fn z_to(d: Vector3<f64>) -> Matrix3<f64> {
    let n = d.norm();
    if n.is_nan() || n <= 0.0 || !n.is_finite() {
        return Matrix3::identity();
    }
    let z = d / n;
    // A helper axis not parallel to z.
    let helper = if z.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let x = helper.cross(&z).normalize();
    let y = z.cross(&x);
    Matrix3::from_columns(&[x, y, z])
}

impl Scene {
    /// An empty scene, z up.
    ///
    /// ```
    /// assert!(lagrange_runtime::scene::Scene::new().shapes.is_empty());
    /// ```
    pub fn new() -> Self {
        Scene {
            shapes: Vec::new(),
            up: Vector3::z(),
        }
    }

    /// Says which direction of the model's coordinates is up (the viewer shows it up): `y` for
    /// a planar model drawn in x, y; `-z` for a bicycle in the benchmark's axes (z down).
    ///
    /// ```
    /// use lagrange_runtime::{scene::Scene, Vector3};
    /// assert_eq!(Scene::new().up(Vector3::y()).up, Vector3::y());
    /// ```
    pub fn up(mut self, up: Vector3<f64>) -> Self {
        self.up = up;
        self
    }

    /// Adds a shape as it is.
    ///
    /// ```
    /// use lagrange_runtime::scene::{Rgb, Geometry, Scene, Shape};
    /// use lagrange_runtime::Vector3;
    /// let s = Scene::new().shape(Shape { name: "b".into(), geometry: Geometry::Sphere { radius: 1.0 },
    ///     position: Vector3::zeros(), rotation: nalgebra::Matrix3::identity(), color: Rgb::RED });
    /// assert_eq!(s.shapes.len(), 1);
    /// ```
    pub fn shape(mut self, shape: Shape) -> Self {
        self.shapes.push(shape);
        self
    }

    fn add(
        self,
        name: &str,
        geometry: Geometry,
        position: Vector3<f64>,
        rotation: Matrix3<f64>,
        color: Rgb,
    ) -> Self {
        self.shape(Shape {
            name: name.to_owned(),
            geometry,
            position,
            rotation,
            color,
        })
    }

    /// A ball of radius `radius` about `center`.
    ///
    /// ```
    /// use lagrange_runtime::scene::{Rgb, Geometry, Scene};
    /// let s = Scene::new().sphere("ball", lagrange_runtime::Vector3::zeros(), 0.5, Rgb::RED);
    /// assert_eq!(s.shapes[0].geometry, Geometry::Sphere { radius: 0.5 });
    /// ```
    pub fn sphere(self, name: &str, center: Vector3<f64>, radius: f64, color: Rgb) -> Self {
        self.add(
            name,
            Geometry::Sphere { radius },
            center,
            Matrix3::identity(),
            color,
        )
    }

    /// A rod (a cylinder of radius `radius`) from `from` to `to`.
    ///
    /// ```
    /// use lagrange_runtime::scene::{Rgb, Geometry, Scene};
    /// use lagrange_runtime::Vector3;
    /// let s = Scene::new().rod("rod", Vector3::zeros(), Vector3::new(0.0, 2.0, 0.0), 0.1, Rgb::GREY);
    /// assert_eq!(s.shapes[0].geometry, Geometry::Cylinder { radius: 0.1, length: 2.0 });
    /// assert_eq!(s.shapes[0].position, Vector3::new(0.0, 1.0, 0.0));
    /// assert!((s.shapes[0].rotation * Vector3::z() - Vector3::y()).norm() < 1e-15);
    /// ```
    pub fn rod(
        self,
        name: &str,
        from: Vector3<f64>,
        to: Vector3<f64>,
        radius: f64,
        color: Rgb,
    ) -> Self {
        let d = to - from;
        self.add(
            name,
            Geometry::Cylinder {
                radius,
                length: d.norm(),
            },
            0.5 * (from + to),
            z_to(d),
            color,
        )
    }

    /// A cylinder of radius `radius` and length `length` centred on `center`, its axis the z
    /// axis of `frame`.
    ///
    /// ```
    /// use lagrange_runtime::{geometry::Rotation, scene::{Rgb, Scene}, Vector3};
    /// let s = Scene::new().cylinder("axle", Rotation::about_x(0.5), Vector3::zeros(), 0.1, 1.0, Rgb::GREY);
    /// assert_eq!(s.shapes[0].rotation, Rotation::about_x(0.5).matrix());
    /// ```
    pub fn cylinder(
        self,
        name: &str,
        frame: Rotation<f64>,
        center: Vector3<f64>,
        radius: f64,
        length: f64,
        color: Rgb,
    ) -> Self {
        self.add(
            name,
            Geometry::Cylinder { radius, length },
            center,
            frame.matrix(),
            color,
        )
    }

    /// A box of full lengths `size` (along the axes of `frame`) centred on `center`.
    ///
    /// ```
    /// use lagrange_runtime::{geometry::Rotation, scene::{Rgb, Geometry, Scene}, Vector3};
    /// let s = Scene::new().cuboid("block", Rotation::identity(), Vector3::zeros(), Vector3::new(1.0, 2.0, 3.0), Rgb::RED);
    /// assert_eq!(s.shapes[0].geometry, Geometry::Cuboid { size: [1.0, 2.0, 3.0] });
    /// ```
    pub fn cuboid(
        self,
        name: &str,
        frame: Rotation<f64>,
        center: Vector3<f64>,
        size: Vector3<f64>,
        color: Rgb,
    ) -> Self {
        self.add(
            name,
            Geometry::Cuboid {
                size: [size.x, size.y, size.z],
            },
            center,
            frame.matrix(),
            color,
        )
    }

    /// A disc (a wheel) of radius `radius` and thickness `thickness` centred on `center`, its
    /// axis the z axis of `frame`.
    ///
    /// ```
    /// use lagrange_runtime::{geometry::Rotation, scene::{Rgb, Geometry, Scene}, Vector3};
    /// let s = Scene::new().disc("wheel", Rotation::identity(), Vector3::zeros(), 0.3, 0.02, Rgb::BLACK);
    /// assert_eq!(s.shapes[0].geometry, Geometry::Disc { radius: 0.3, thickness: 0.02 });
    /// ```
    pub fn disc(
        self,
        name: &str,
        frame: Rotation<f64>,
        center: Vector3<f64>,
        radius: f64,
        thickness: f64,
        color: Rgb,
    ) -> Self {
        self.add(
            name,
            Geometry::Disc { radius, thickness },
            center,
            frame.matrix(),
            color,
        )
    }

    /// The trace of `point`: a line through the positions it takes during the run (the
    /// page draws it up to the time shown).
    ///
    /// ```
    /// use lagrange_runtime::scene::{Rgb, Geometry, Scene};
    /// let s = Scene::new().trace("tip", lagrange_runtime::Vector3::x(), Rgb::RED);
    /// assert_eq!(s.shapes[0].geometry, Geometry::Trace);
    /// ```
    pub fn trace(self, name: &str, point: Vector3<f64>, color: Rgb) -> Self {
        self.add(name, Geometry::Trace, point, Matrix3::identity(), color)
    }
}

/// A system that can be drawn: the shapes at a state, from the positions (and the time).
/// `#[lagrangian]` writes it from `fn scene`; by hand:
///
/// ```
/// use lagrange_runtime::scene::{Rgb, Scene, Visual};
/// use lagrange_runtime::Vector3;
/// struct Ball;
/// impl Visual<1> for Ball {
///     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
///         Scene::new().sphere("ball", Vector3::new(0.0, 0.0, q[0]), 0.1, Rgb::RED)
///     }
/// }
/// assert_eq!(Ball.scene(&[2.0], 0.0).shapes[0].position.z, 2.0);
/// ```
pub trait Visual<const N: usize> {
    /// The shapes at the positions `q` and the time `t` (the same shapes, by name and kind, at
    /// every state of a run).
    fn scene(&self, q: &[f64; N], t: f64) -> Scene;
}
