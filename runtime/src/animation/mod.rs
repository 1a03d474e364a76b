//! A run as a 3-D animation: the [`Scene`] of a [`Visual`] system at the run's samples
//! (decimated to what the eye needs), written as a glTF 2.0 file ([`Trajectory::write_gltf`])
//! or as one self-contained web page that plays it with three.js ([`Trajectory::write_html`]).
//!
//! The glTF file has one node per shape under a root node that turns the model's up direction
//! to glTF's +y, each shape's translation and rotation keyframed at the kept samples (the time
//! axis the run's, shifted to start at 0: the run's start is in the scene's extras), a trace as a
//! line through the point's kept positions, and a camera that sees the whole motion.

mod gltf;
mod mesh;
mod page;

use std::fmt;
use std::path::{Path, PathBuf};

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

use crate::Trajectory;
use crate::scene::{Geometry, Scene, Visual};

/// The most keyframes an animation keeps by default: 3000, spread evenly over the run (50 s at
/// 60 frames per second), plus the states at every jump.
///
/// ```
/// assert_eq!(lagrange_runtime::animation::DEFAULT_MAX_FRAMES, 3000);
/// ```
pub const DEFAULT_MAX_FRAMES: usize = 3000;

/// Why an animation could not be made or written: what, where, and what to try.
///
/// ```
/// use lagrange_runtime::animation::AnimationError;
/// let e = AnimationError::NoSamples;
/// assert!(e.to_string().contains("no samples"));
/// ```
#[derive(Debug)]
#[non_exhaustive]
pub enum AnimationError {
    /// The trajectory has no samples (a run that kept none, or an empty one).
    NoSamples,
    /// The scene has no shapes.
    NoShapes,
    /// A shape's size is not a finite number ≥ 0.
    BadSize {
        /// The shape.
        shape: String,
        /// Which size (`radius`, `length`, …).
        size: &'static str,
        /// Its value.
        value: f64,
        /// The time of the state where it was.
        t: f64,
    },
    /// A shape's position or rotation is not finite, or its rotation is not a rotation.
    BadPlacement {
        /// The shape.
        shape: String,
        /// What is wrong.
        what: String,
        /// The time of the state.
        t: f64,
    },
    /// Two shapes have the same name.
    DuplicateName {
        /// The name.
        name: String,
    },
    /// The scene at time `t` has other shapes (names or kinds) than at the start.
    ShapesChanged {
        /// The time.
        t: f64,
        /// What differs.
        what: String,
    },
    /// The file could not be written.
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
}

impl fmt::Display for AnimationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AnimationError::NoSamples => write!(
                f,
                "the trajectory has no samples to animate: run with samples kept \
                 (`.sample_every(dt)` and `keep_samples(true)`, the default) and check that the \
                 run took a step"
            ),
            AnimationError::NoShapes => write!(
                f,
                "the scene has no shapes: add some in `fn scene` (`Scene::new().sphere(\"bob\", \
                 p, 0.1, Rgb::RED)`)"
            ),
            AnimationError::BadSize {
                shape,
                size,
                value,
                t,
            } => write!(
                f,
                "shape `{shape}` has {size} = {value} at t = {t}: sizes are finite and ≥ 0; \
                 check the parameter or the expression it comes from in `fn scene`"
            ),
            AnimationError::BadPlacement { shape, what, t } => write!(
                f,
                "shape `{shape}` at t = {t}: {what}; place shapes with `Vector3` and turn them \
                 with `Rotation` (`about_x/y/z`, `from_quaternion` of a unit quaternion) in \
                 `fn scene`"
            ),
            AnimationError::DuplicateName { name } => write!(
                f,
                "two shapes are named `{name}`: each shape's name is its node's in the glTF file, \
                 so names are unique; rename one"
            ),
            AnimationError::ShapesChanged { t, what } => write!(
                f,
                "the scene at t = {t} is not the scene at the start ({what}): `fn scene` returns \
                 the same shapes, by name and kind, at every state, only their places change; \
                 hide a shape by making it small instead"
            ),
            AnimationError::Io { path, source } => {
                write!(f, "writing {}: {source}", path.display())
            }
        }
    }
}

impl std::error::Error for AnimationError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            AnimationError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// The default camera: where it is, where it looks, its vertical field of view, in the glTF
/// world (y up). The page starts there (the mouse then orbits about the target).
///
/// ```
/// use lagrange_runtime::animation::Camera;
/// let c = Camera { position: [0.0, 0.0, 5.0], target: [0.0; 3], fov_y_deg: 45.0, near: 0.1, far: 100.0 };
/// let p = c.project([0.0, 0.0, 0.0], 800.0, 600.0);
/// assert!((p[0] - 400.0).abs() < 1e-9 && (p[1] - 300.0).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The eye.
    pub position: [f64; 3],
    /// The point looked at (the motion's centre).
    pub target: [f64; 3],
    /// The vertical field of view, degrees.
    pub fov_y_deg: f64,
    /// The near clipping distance.
    pub near: f64,
    /// The far clipping distance.
    pub far: f64,
}

impl Camera {
    /// The pixel (from the top left) where a point of the glTF world appears in a view of
    /// `width` × `height` pixels, with y up on the screen as three.js's `lookAt` makes it.
    ///
    /// ```
    /// use lagrange_runtime::animation::Camera;
    /// let c = Camera { position: [0.0, 0.0, 5.0], target: [0.0; 3], fov_y_deg: 90.0, near: 0.1, far: 100.0 };
    /// // At distance 5 and a 90° field of view, y = 5 is the top edge.
    /// assert!((c.project([0.0, 5.0, 0.0], 800.0, 600.0)[1]).abs() < 1e-9);
    /// ```
    pub fn project(&self, p: [f64; 3], width: f64, height: f64) -> [f64; 2] {
        let eye = Vector3::from(self.position);
        let target = Vector3::from(self.target);
        let back = (eye - target).normalize();
        let right = Vector3::y().cross(&back).normalize();
        let up = back.cross(&right);
        let d = Vector3::from(p) - eye;
        let (x, y, z) = (d.dot(&right), d.dot(&up), d.dot(&back));
        let f = 1.0 / (self.fov_y_deg.to_radians() / 2.0).tan();
        let aspect = width / height;
        let (nx, ny) = (f / aspect * x / -z, f * y / -z);
        [(nx + 1.0) / 2.0 * width, (1.0 - ny) / 2.0 * height]
    }
}

/// A run's animation: the kept keyframes (times and scenes) and the default camera. Made by
/// [`Animation::of`]; written by [`Animation::write_gltf`] and [`Animation::write_html`] (what
/// [`Trajectory::write_gltf`] and [`Trajectory::write_html`] do with the default bound).
///
/// ```
/// use lagrange_runtime::animation::Animation;
/// use lagrange_runtime::scene::{Rgb, Scene, Visual};
/// use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation, Vector3};
/// struct Free;
/// impl Lagrangian<1> for Free {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [true];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
/// }
/// impl Visual<1> for Free {
///     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
///         Scene::new().sphere("ball", Vector3::new(q[0], 0.0, 0.0), 0.1, Rgb::RED)
///     }
/// }
/// let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.01 }).until(10.0).run().unwrap();
/// let anim = Animation::of(&tr, &Free).max_frames(101).build().unwrap();
/// assert_eq!(anim.times().len(), 101);
/// assert!((anim.scenes()[100].shapes[0].position.x - 10.0).abs() < 1e-12);
/// ```
#[derive(Clone, Debug)]
pub struct Animation {
    times: Vec<f64>,
    scenes: Vec<Scene>,
    camera: Camera,
    up: UnitQuaternion<f64>,
    title: String,
}

/// How [`Animation::of`] makes an animation: the bound on keyframes, then [`AnimationBuilder::build`].
///
/// ```
/// # use lagrange_runtime::animation::DEFAULT_MAX_FRAMES;
/// assert!(DEFAULT_MAX_FRAMES > 1000);
/// ```
pub struct AnimationBuilder<'a, V: ?Sized, const N: usize> {
    traj: &'a Trajectory<N>,
    sys: &'a V,
    max_frames: usize,
    title: String,
}

impl<V: Visual<N> + ?Sized, const N: usize> AnimationBuilder<'_, V, N> {
    /// The most keyframes kept, spread evenly over the run (at least 2; the states at jumps
    /// come on top). Default [`DEFAULT_MAX_FRAMES`].
    ///
    /// ```
    /// # use lagrange_runtime::animation::Animation;
    /// # use lagrange_runtime::scene::{Rgb, Scene, Visual};
    /// # use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation, Vector3};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// # impl Visual<1> for Free {
    /// #     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
    /// #         Scene::new().sphere("ball", Vector3::new(q[0], 0.0, 0.0), 0.1, Rgb::RED)
    /// #     }
    /// # }
    /// # let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.5 }).until(1.0).run().unwrap();
    /// let anim = Animation::of(&tr, &Free).max_frames(2).build().unwrap();
    /// assert_eq!(anim.times(), &[0.0, 1.0]);
    /// ```
    pub fn max_frames(mut self, n: usize) -> Self {
        self.max_frames = n.max(2);
        self
    }

    /// The page's title (default "lagrange").
    ///
    /// ```
    /// # use lagrange_runtime::animation::Animation;
    /// # use lagrange_runtime::scene::{Rgb, Scene, Visual};
    /// # use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation, Vector3};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// # impl Visual<1> for Free {
    /// #     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
    /// #         Scene::new().sphere("ball", Vector3::new(q[0], 0.0, 0.0), 0.1, Rgb::RED)
    /// #     }
    /// # }
    /// # let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.5 }).until(1.0).run().unwrap();
    /// let anim = Animation::of(&tr, &Free).title("free particle").build().unwrap();
    /// assert!(anim.html().contains("<title>free particle</title>"));
    /// ```
    pub fn title(mut self, title: &str) -> Self {
        self.title = title.to_owned();
        self
    }

    /// Evaluates the scene at the kept samples and checks it.
    ///
    /// ```
    /// # use lagrange_runtime::animation::Animation;
    /// # use lagrange_runtime::scene::{Rgb, Scene, Visual};
    /// # use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation, Vector3};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// # impl Visual<1> for Free {
    /// #     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
    /// #         Scene::new().sphere("ball", Vector3::new(q[0], 0.0, 0.0), 0.1, Rgb::RED)
    /// #     }
    /// # }
    /// # let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.5 }).until(1.0).run().unwrap();
    /// let anim = Animation::of(&tr, &Free).build().unwrap();
    /// assert_eq!(anim.scenes().len(), 3);
    /// ```
    pub fn build(self) -> Result<Animation, AnimationError> {
        let frames = keyframes(self.traj, self.max_frames);
        if frames.is_empty() {
            return Err(AnimationError::NoSamples);
        }
        let mut scenes = Vec::with_capacity(frames.len());
        for (t, q) in &frames {
            let scene = self.sys.scene(q, *t);
            check(&scene, *t, scenes.first())?;
            scenes.push(scene);
        }
        let times: Vec<f64> = frames.iter().map(|f| f.0).collect();
        let up = up_rotation(scenes[0].up);
        let camera = default_camera(&scenes, &up);
        Ok(Animation {
            times,
            scenes,
            camera,
            up,
            title: self.title,
        })
    }
}

impl Animation {
    /// The animation of run `traj` of system `sys`, to be configured and built.
    ///
    /// ```
    /// # use lagrange_runtime::animation::Animation;
    /// # use lagrange_runtime::scene::{Rgb, Scene, Visual};
    /// # use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation, Vector3};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// # impl Visual<1> for Free {
    /// #     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
    /// #         Scene::new().sphere("ball", Vector3::new(q[0], 0.0, 0.0), 0.1, Rgb::RED)
    /// #     }
    /// # }
    /// # let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.5 }).until(1.0).run().unwrap();
    /// let anim = Animation::of(&tr, &Free).build().unwrap();
    /// assert_eq!(anim.times().len(), tr.t.len());
    /// ```
    pub fn of<'a, V: Visual<N> + ?Sized, const N: usize>(
        traj: &'a Trajectory<N>,
        sys: &'a V,
    ) -> AnimationBuilder<'a, V, N> {
        AnimationBuilder {
            traj,
            sys,
            max_frames: DEFAULT_MAX_FRAMES,
            title: "lagrange".to_owned(),
        }
    }

    /// The keyframes' times (the run's).
    ///
    /// ```
    /// # use lagrange_runtime::animation::Animation;
    /// # use lagrange_runtime::scene::{Rgb, Scene, Visual};
    /// # use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation, Vector3};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// # impl Visual<1> for Free {
    /// #     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
    /// #         Scene::new().sphere("ball", Vector3::new(q[0], 0.0, 0.0), 0.1, Rgb::RED)
    /// #     }
    /// # }
    /// # let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.5 }).until(1.0).run().unwrap();
    /// let anim = Animation::of(&tr, &Free).build().unwrap();
    /// assert_eq!(anim.times(), &[0.0, 0.5, 1.0]);
    /// ```
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// The scene at each keyframe.
    ///
    /// ```
    /// # use lagrange_runtime::animation::Animation;
    /// # use lagrange_runtime::scene::{Rgb, Scene, Visual};
    /// # use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation, Vector3};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// # impl Visual<1> for Free {
    /// #     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
    /// #         Scene::new().sphere("ball", Vector3::new(q[0], 0.0, 0.0), 0.1, Rgb::RED)
    /// #     }
    /// # }
    /// # let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.5 }).until(1.0).run().unwrap();
    /// let anim = Animation::of(&tr, &Free).build().unwrap();
    /// assert_eq!(anim.scenes()[2].shapes[0].position.x, tr.q[2][0]);
    /// ```
    pub fn scenes(&self) -> &[Scene] {
        &self.scenes
    }

    /// The default camera.
    ///
    /// ```
    /// # use lagrange_runtime::animation::Animation;
    /// # use lagrange_runtime::scene::{Rgb, Scene, Visual};
    /// # use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation, Vector3};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// # impl Visual<1> for Free {
    /// #     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
    /// #         Scene::new().sphere("ball", Vector3::new(q[0], 0.0, 0.0), 0.1, Rgb::RED)
    /// #     }
    /// # }
    /// # let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.5 }).until(1.0).run().unwrap();
    /// let anim = Animation::of(&tr, &Free).build().unwrap();
    /// // It looks at the middle of the motion: x from 0 to 1, z up turned to glTF's y up.
    /// assert!((anim.camera().target[0] - 0.5).abs() < 1e-12);
    /// ```
    pub fn camera(&self) -> Camera {
        self.camera
    }

    /// A point of the model's coordinates in the glTF world (y up): turned by the root node's
    /// rotation, which takes the scene's up direction to +y.
    ///
    /// ```
    /// # use lagrange_runtime::animation::Animation;
    /// # use lagrange_runtime::scene::{Rgb, Scene, Visual};
    /// # use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation, Vector3};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// # impl Visual<1> for Free {
    /// #     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
    /// #         Scene::new().sphere("ball", Vector3::new(q[0], 0.0, 0.0), 0.1, Rgb::RED)
    /// #     }
    /// # }
    /// # let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.5 }).until(1.0).run().unwrap();
    /// let anim = Animation::of(&tr, &Free).build().unwrap();
    /// // z up in the model is y up in the glTF world.
    /// let w = anim.to_world(Vector3::z());
    /// assert!((w[1] - 1.0).abs() < 1e-15 && w[2].abs() < 1e-15);
    /// ```
    pub fn to_world(&self, p: Vector3<f64>) -> [f64; 3] {
        let w = self.up * p;
        [w.x, w.y, w.z]
    }

    /// The glTF 2.0 document (JSON, the buffer embedded as a base64 `data:` URI).
    ///
    /// ```
    /// # use lagrange_runtime::animation::Animation;
    /// # use lagrange_runtime::scene::{Rgb, Scene, Visual};
    /// # use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation, Vector3};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// # impl Visual<1> for Free {
    /// #     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
    /// #         Scene::new().sphere("ball", Vector3::new(q[0], 0.0, 0.0), 0.1, Rgb::RED)
    /// #     }
    /// # }
    /// # let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.5 }).until(1.0).run().unwrap();
    /// let anim = Animation::of(&tr, &Free).build().unwrap();
    /// assert!(anim.gltf_json().contains("\"version\":\"2.0\""));
    /// ```
    pub fn gltf_json(&self) -> String {
        gltf::document(self)
    }

    /// The web page that plays the animation (three.js embedded; no network needed).
    ///
    /// ```
    /// # use lagrange_runtime::animation::Animation;
    /// # use lagrange_runtime::scene::{Rgb, Scene, Visual};
    /// # use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation, Vector3};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// # impl Visual<1> for Free {
    /// #     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
    /// #         Scene::new().sphere("ball", Vector3::new(q[0], 0.0, 0.0), 0.1, Rgb::RED)
    /// #     }
    /// # }
    /// # let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.5 }).until(1.0).run().unwrap();
    /// let anim = Animation::of(&tr, &Free).build().unwrap();
    /// assert!(anim.html().contains("<script type=\"importmap\">"));
    /// ```
    pub fn html(&self) -> String {
        page::html(self, &self.gltf_json())
    }

    /// Writes the glTF file (missing parent folders are created).
    ///
    /// ```
    /// # use lagrange_runtime::animation::Animation;
    /// # use lagrange_runtime::scene::{Rgb, Scene, Visual};
    /// # use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation, Vector3};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// # impl Visual<1> for Free {
    /// #     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
    /// #         Scene::new().sphere("ball", Vector3::new(q[0], 0.0, 0.0), 0.1, Rgb::RED)
    /// #     }
    /// # }
    /// # let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.5 }).until(1.0).run().unwrap();
    /// let path = std::env::temp_dir().join("lagrange_doctest_anim.gltf");
    /// Animation::of(&tr, &Free).build().unwrap().write_gltf(&path).unwrap();
    /// assert!(std::fs::read_to_string(&path).unwrap().starts_with('{'));
    /// ```
    pub fn write_gltf(&self, path: impl AsRef<Path>) -> Result<(), AnimationError> {
        write(path.as_ref(), &self.gltf_json())
    }

    /// Writes the web page (missing parent folders are created).
    ///
    /// ```
    /// # use lagrange_runtime::animation::Animation;
    /// # use lagrange_runtime::scene::{Rgb, Scene, Visual};
    /// # use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation, Vector3};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// # impl Visual<1> for Free {
    /// #     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
    /// #         Scene::new().sphere("ball", Vector3::new(q[0], 0.0, 0.0), 0.1, Rgb::RED)
    /// #     }
    /// # }
    /// # let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.5 }).until(1.0).run().unwrap();
    /// let path = std::env::temp_dir().join("lagrange_doctest_anim.html");
    /// Animation::of(&tr, &Free).build().unwrap().write_html(&path).unwrap();
    /// assert!(std::fs::read_to_string(&path).unwrap().starts_with("<!DOCTYPE html>"));
    /// ```
    pub fn write_html(&self, path: impl AsRef<Path>) -> Result<(), AnimationError> {
        write(path.as_ref(), &self.html())
    }
}

fn write(path: &Path, text: &str) -> Result<(), AnimationError> {
    let io = |source| AnimationError::Io {
        path: path.to_owned(),
        source,
    };
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(io)?;
    }
    std::fs::write(path, text).map_err(io)
}

impl<const N: usize> Trajectory<N> {
    /// Writes the run as a glTF 2.0 animation of `sys`'s scene ([`Visual`]): one node per shape,
    /// its translation and rotation keyframed at the samples (at most [`DEFAULT_MAX_FRAMES`],
    /// evenly spread, and the states at every jump), the time axis the run's. Blender, three.js
    /// and any glTF viewer open it.
    ///
    /// ```
    /// use lagrange_runtime::scene::{Rgb, Scene, Visual};
    /// use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation, Vector3};
    /// struct Free;
    /// impl Lagrangian<1> for Free {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [true];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// }
    /// impl Visual<1> for Free {
    ///     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
    ///         Scene::new().sphere("ball", Vector3::new(q[0], 0.0, 0.0), 0.1, Rgb::RED)
    ///     }
    /// }
    /// let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.5 }).until(1.0).run().unwrap();
    /// let path = std::env::temp_dir().join("lagrange_doctest_free.gltf");
    /// tr.write_gltf(&path, &Free).unwrap();
    /// assert!(std::fs::read_to_string(&path).unwrap().contains("\"ball\""));
    /// ```
    pub fn write_gltf<V: Visual<N> + ?Sized>(
        &self,
        path: impl AsRef<Path>,
        sys: &V,
    ) -> Result<(), AnimationError> {
        Animation::of(self, sys).build()?.write_gltf(path)
    }

    /// Writes one self-contained web page that plays the run in 3-D (three.js embedded, no
    /// network needed): play and pause, a time slider, the speed, the camera orbiting with the
    /// mouse (zoom with the wheel), the trace of a chosen point. The keyframes are
    /// [`Trajectory::write_gltf`]'s.
    ///
    /// ```
    /// use lagrange_runtime::scene::{Rgb, Scene, Visual};
    /// use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation, Vector3};
    /// struct Free;
    /// impl Lagrangian<1> for Free {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [true];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// }
    /// impl Visual<1> for Free {
    ///     fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
    ///         Scene::new().sphere("ball", Vector3::new(q[0], 0.0, 0.0), 0.1, Rgb::RED)
    ///     }
    /// }
    /// let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.5 }).until(1.0).run().unwrap();
    /// let path = std::env::temp_dir().join("lagrange_doctest_free.html");
    /// tr.write_html(&path, &Free).unwrap();
    /// assert!(std::fs::read_to_string(&path).unwrap().starts_with("<!DOCTYPE html>"));
    /// ```
    pub fn write_html<V: Visual<N> + ?Sized>(
        &self,
        path: impl AsRef<Path>,
        sys: &V,
    ) -> Result<(), AnimationError> {
        Animation::of(self, sys).build()?.write_html(path)
    }
}

/// The states kept: the first and the last sample and, for each of `max_frames` times evenly
/// spread over the run, the first sample at or after it (so at most `max_frames`), and at every
/// jump the state before it (and the state after it, a hair later, if the positions jump). The
/// times since the start strictly increase in f32 (glTF's time type).
pub(crate) fn keyframes<const N: usize>(
    traj: &Trajectory<N>,
    max_frames: usize,
) -> Vec<(f64, [f64; N])> {
    let n = traj.t.len().min(traj.q.len());
    if n == 0 {
        return Vec::new();
    }
    let (t0, t1) = (traj.t[0], traj.t[n - 1]);
    let spacing = (t1 - t0) / (max_frames.max(2) - 1) as f64;
    let since = |t: f64| (t - t0) as f32;
    let mut kept: Vec<(f64, [f64; N])> = Vec::new();
    let push = |kept: &mut Vec<(f64, [f64; N])>, t: f64, q: [f64; N]| {
        if let Some(last) = kept.last_mut()
            && since(t) <= since(last.0)
        {
            if t == last.0 {
                // The same instant again (a sample at a jump): the later state wins.
                last.1 = q;
            }
            return;
        }
        kept.push((t, q));
    };
    let mut jumps = traj.jumps.iter().peekable();
    let mut target = 0_usize;
    for k in 0..n {
        let t = traj.t[k];
        while let Some(j) = jumps.next_if(|j| j.t <= t) {
            push(&mut kept, j.t, j.before.0);
            if j.after.0 != j.before.0 {
                let later = t0 + f64::from(next_f32_up(since(j.t)));
                push(&mut kept, later, j.after.0);
            }
        }
        // Whether the run has reached target time `m` (a sample a rounding error short of it
        // counts).
        let reached = |m: usize| t - t0 >= (m as f64 * spacing) * (1.0 - 1e-12);
        if k == 0 || k == n - 1 || reached(target) {
            push(&mut kept, t, traj.q[k]);
            // The next time not yet reached.
            while target < max_frames && reached(target) {
                target += 1;
            }
        }
    }
    kept
}

/// The next f32 above `x` (for x ≥ 0 and finite).
fn next_f32_up(x: f32) -> f32 {
    if x == 0.0 {
        f32::from_bits(1)
    } else if x > 0.0 {
        f32::from_bits(x.to_bits() + 1)
    } else {
        f32::from_bits(x.to_bits() - 1)
    }
}

/// The checks of a scene at time `t` against the first one.
fn check(scene: &Scene, t: f64, first: Option<&Scene>) -> Result<(), AnimationError> {
    if scene.shapes.is_empty() {
        return Err(AnimationError::NoShapes);
    }
    for (i, s) in scene.shapes.iter().enumerate() {
        if scene.shapes[..i].iter().any(|o| o.name == s.name) {
            return Err(AnimationError::DuplicateName {
                name: s.name.clone(),
            });
        }
        for (size, value) in s.geometry.sizes() {
            if !(value.is_finite() && value >= 0.0) {
                return Err(AnimationError::BadSize {
                    shape: s.name.clone(),
                    size,
                    value,
                    t,
                });
            }
        }
        let bad = |what: String| AnimationError::BadPlacement {
            shape: s.name.clone(),
            what,
            t,
        };
        if s.position.iter().any(|x| !x.is_finite()) {
            return Err(bad(format!(
                "its position ({}, {}, {}) is not finite",
                s.position.x, s.position.y, s.position.z
            )));
        }
        let r = &s.rotation;
        if r.iter().any(|x| !x.is_finite()) {
            return Err(bad("its rotation is not finite".to_owned()));
        }
        let off = (r.transpose() * r - Matrix3::identity()).abs().max();
        if off > 1e-6 || r.determinant() < 0.0 {
            return Err(bad(format!(
                "its rotation matrix is not a rotation (|RᵀR − I| = {off:.1e}, det R = {:.3})",
                r.determinant()
            )));
        }
    }
    if !scene.up.iter().all(|x| x.is_finite()) || scene.up.norm() == 0.0 {
        return Err(AnimationError::BadPlacement {
            shape: "(the scene's up direction)".to_owned(),
            what: "`Scene::up` is zero or not finite".to_owned(),
            t,
        });
    }
    if let Some(first) = first {
        if first.shapes.len() != scene.shapes.len() {
            return Err(AnimationError::ShapesChanged {
                t,
                what: format!(
                    "{} shapes, against {} at the start",
                    scene.shapes.len(),
                    first.shapes.len()
                ),
            });
        }
        for (a, b) in first.shapes.iter().zip(&scene.shapes) {
            if a.name != b.name || a.geometry.kind() != b.geometry.kind() {
                return Err(AnimationError::ShapesChanged {
                    t,
                    what: format!(
                        "{} `{}` where the start has {} `{}`",
                        b.geometry.kind(),
                        b.name,
                        a.geometry.kind(),
                        a.name
                    ),
                });
            }
        }
    }
    Ok(())
}

/// The rotation taking the model's up direction to glTF's +y (z up: −90° about x).
fn up_rotation(up: Vector3<f64>) -> UnitQuaternion<f64> {
    let up = up.normalize();
    if (up - Vector3::z()).norm() < 1e-12 {
        return UnitQuaternion::from_axis_angle(&Vector3::x_axis(), -std::f64::consts::FRAC_PI_2);
    }
    UnitQuaternion::rotation_between(&up, &Vector3::y()).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    })
}

/// A camera that sees every shape at every keyframe: looking at the centre of their bounding
/// box from above and to the side, far enough for the bounding sphere to fit.
fn default_camera(scenes: &[Scene], up: &UnitQuaternion<f64>) -> Camera {
    let (mut lo, mut hi) = (
        Vector3::repeat(f64::INFINITY),
        Vector3::repeat(f64::NEG_INFINITY),
    );
    for scene in scenes {
        for s in &scene.shapes {
            let p = up * s.position;
            let e = s.geometry.extent();
            lo = lo.inf(&(p - Vector3::repeat(e)));
            hi = hi.sup(&(p + Vector3::repeat(e)));
        }
    }
    let center = 0.5 * (lo + hi);
    let radius = (0.5 * (hi - lo).norm()).max(1e-3);
    let fov_y_deg: f64 = 40.0;
    let distance = 1.02 * radius / (fov_y_deg.to_radians() / 2.0).sin();
    let dir = Vector3::new(0.55, 0.45, 1.0).normalize();
    let eye = center + distance * dir;
    Camera {
        position: [eye.x, eye.y, eye.z],
        target: [center.x, center.y, center.z],
        fov_y_deg,
        near: distance / 100.0,
        far: distance * 10.0,
    }
}

/// The unit quaternion of a rotation matrix.
pub(crate) fn quaternion(m: &Matrix3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*m))
}

/// Whether the shape is drawn as a mesh (not a trace).
pub(crate) fn is_mesh(g: &Geometry) -> bool {
    !matches!(g, Geometry::Trace)
}
