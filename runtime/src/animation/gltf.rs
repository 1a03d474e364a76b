//! The glTF 2.0 document of an animation, built with `gltf-json` (the glTF crate's own types and
//! serializer): one buffer (embedded as a base64 `data:` URI) holding the meshes, the keyframe
//! times and each shape's translations and rotations; one node per shape under a root node that
//! turns the model's up direction to +y; one animation; a camera.

use base64::Engine;
use gltf_json as json;
use json::validation::Checked::Valid;
use json::validation::USize64;
use nalgebra::UnitQuaternion;

use super::{Animation, is_mesh, mesh, quaternion};
use crate::scene::Geometry;

/// The buffer being filled and the accessors into it.
struct Builder {
    root: json::Root,
    bytes: Vec<u8>,
    buffer: json::Index<json::Buffer>,
}

impl Builder {
    /// A view of `data` (aligned to 4 bytes) and an accessor of `count` elements of `ty`.
    #[allow(clippy::too_many_arguments)]
    fn accessor(
        &mut self,
        data: &[u8],
        count: usize,
        component: json::accessor::ComponentType,
        ty: json::accessor::Type,
        target: Option<json::buffer::Target>,
        min_max: Option<(serde_json::Value, serde_json::Value)>,
    ) -> json::Index<json::Accessor> {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        let offset = self.bytes.len();
        self.bytes.extend_from_slice(data);
        let view = self.root.push(json::buffer::View {
            buffer: self.buffer,
            byte_length: USize64::from(data.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: target.map(Valid),
            extensions: None,
            extras: Default::default(),
        });
        let (min, max) = match min_max {
            Some((a, b)) => (Some(a), Some(b)),
            None => (None, None),
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(ty),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    fn vec3(
        &mut self,
        v: &[[f32; 3]],
        target: Option<json::buffer::Target>,
        bounds: bool,
    ) -> json::Index<json::Accessor> {
        let data: Vec<u8> = v.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
        let min_max = bounds.then(|| {
            let mut lo = [f32::INFINITY; 3];
            let mut hi = [f32::NEG_INFINITY; 3];
            for p in v {
                for i in 0..3 {
                    lo[i] = lo[i].min(p[i]);
                    hi[i] = hi[i].max(p[i]);
                }
            }
            (serde_json::json!(lo), serde_json::json!(hi))
        });
        self.accessor(
            &data,
            v.len(),
            json::accessor::ComponentType::F32,
            json::accessor::Type::Vec3,
            target,
            min_max,
        )
    }
}

/// The extras the page reads: the run's start time and the default camera.
fn scene_extras(anim: &Animation) -> json::Extras {
    let c = anim.camera;
    let value = serde_json::json!({
        "lagrange": {
            "t0": anim.times[0],
            "camera": {
                "position": c.position,
                "target": c.target,
                "fov_y_deg": c.fov_y_deg,
                "near": c.near,
                "far": c.far,
            }
        }
    });
    serde_json::value::to_raw_value(&value).ok()
}

/// The colour as a glTF base colour (linear, from sRGB).
fn linear(c: f64) -> f32 {
    let c = c.clamp(0.0, 1.0);
    let l = if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    };
    l as f32
}

impl Builder {
    /// The mesh primitive of shape `i` of `anim` with its `material`: a body's triangles, or a
    /// trace's line strip through the point's kept positions.
    fn primitive(
        &mut self,
        anim: &Animation,
        i: usize,
        material: json::Index<json::Material>,
    ) -> json::mesh::Primitive {
        match mesh::of(&anim.scenes[0].shapes[i].geometry) {
            Some(m) => {
                let positions =
                    self.vec3(&m.positions, Some(json::buffer::Target::ArrayBuffer), true);
                let normals = self.vec3(&m.normals, Some(json::buffer::Target::ArrayBuffer), false);
                let index_bytes: Vec<u8> = m.indices.iter().flat_map(|x| x.to_le_bytes()).collect();
                let indices = self.accessor(
                    &index_bytes,
                    m.indices.len(),
                    json::accessor::ComponentType::U16,
                    json::accessor::Type::Scalar,
                    Some(json::buffer::Target::ElementArrayBuffer),
                    None,
                );
                json::mesh::Primitive {
                    attributes: [
                        (Valid(json::mesh::Semantic::Positions), positions),
                        (Valid(json::mesh::Semantic::Normals), normals),
                    ]
                    .into_iter()
                    .collect(),
                    extensions: None,
                    extras: Default::default(),
                    indices: Some(indices),
                    material: Some(material),
                    mode: Valid(json::mesh::Mode::Triangles),
                    targets: None,
                }
            }
            None => {
                // A trace: the point's kept positions, a line strip in the model's coordinates.
                let points: Vec<[f32; 3]> = anim
                    .scenes
                    .iter()
                    .map(|s| s.shapes[i].position.map(|x| x as f32).into())
                    .collect();
                let positions = self.vec3(&points, Some(json::buffer::Target::ArrayBuffer), true);
                json::mesh::Primitive {
                    attributes: [(Valid(json::mesh::Semantic::Positions), positions)]
                        .into_iter()
                        .collect(),
                    extensions: None,
                    extras: Default::default(),
                    indices: None,
                    material: Some(material),
                    mode: Valid(json::mesh::Mode::LineStrip),
                    targets: None,
                }
            }
        }
    }

    /// The keyframes of shape `i` of `anim` (its node `node`, on the key times `input`): a
    /// sampler and a channel each for its translations and its rotations.
    fn keyframes(
        &mut self,
        anim: &Animation,
        i: usize,
        (input, node): (json::Index<json::Accessor>, json::Index<json::Node>),
        (samplers, channels): (
            &mut Vec<json::animation::Sampler>,
            &mut Vec<json::animation::Channel>,
        ),
    ) {
        // Keyframes: the translations and the rotations (each quaternion on the side of the
        // previous one, so that every viewer interpolates the short way).
        let translations: Vec<[f32; 3]> = anim
            .scenes
            .iter()
            .map(|s| s.shapes[i].position.map(|x| x as f32).into())
            .collect();
        let mut rotations: Vec<[f32; 4]> = Vec::with_capacity(anim.scenes.len());
        let mut previous: Option<UnitQuaternion<f64>> = None;
        for s in &anim.scenes {
            let mut q = quaternion(&s.shapes[i].rotation);
            if previous.is_some_and(|p| p.coords.dot(&q.coords) < 0.0) {
                q = UnitQuaternion::new_unchecked(-q.into_inner());
            }
            previous = Some(q);
            rotations.push([q.i as f32, q.j as f32, q.k as f32, q.w as f32]);
        }
        let t_out = self.vec3(&translations, None, false);
        let r_bytes: Vec<u8> = rotations
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let r_out = self.accessor(
            &r_bytes,
            rotations.len(),
            json::accessor::ComponentType::F32,
            json::accessor::Type::Vec4,
            None,
            None,
        );
        for (out, path) in [
            (t_out, json::animation::Property::Translation),
            (r_out, json::animation::Property::Rotation),
        ] {
            let sampler = json::Index::new(samplers.len() as u32);
            samplers.push(json::animation::Sampler {
                extensions: None,
                extras: Default::default(),
                input,
                interpolation: Valid(json::animation::Interpolation::Linear),
                output: out,
            });
            channels.push(json::animation::Channel {
                sampler,
                target: json::animation::Target {
                    extensions: None,
                    extras: Default::default(),
                    node,
                    path: Valid(path),
                },
                extensions: None,
                extras: Default::default(),
            });
        }
    }

    /// The default camera of `anim`, as a camera node (Blender and other viewers offer it).
    fn camera(&mut self, anim: &Animation) -> json::Index<json::Node> {
        let c = anim.camera;
        let camera = self.root.push(json::Camera {
            name: Some("default".to_owned()),
            orthographic: None,
            perspective: Some(json::camera::Perspective {
                aspect_ratio: None,
                yfov: c.fov_y_deg.to_radians() as f32,
                zfar: Some(c.far as f32),
                znear: c.near as f32,
                extensions: None,
                extras: Default::default(),
            }),
            type_: Valid(json::camera::Type::Perspective),
            extensions: None,
            extras: Default::default(),
        });
        let look = look_at(c.position, c.target);
        self.root.push(json::Node {
            name: Some("camera".to_owned()),
            camera: Some(camera),
            translation: Some(c.position.map(|x| x as f32)),
            rotation: Some(json::scene::UnitQuaternion([
                look.i as f32,
                look.j as f32,
                look.k as f32,
                look.w as f32,
            ])),
            ..Default::default()
        })
    }
}

/// The glTF JSON of `anim`.
pub(super) fn document(anim: &Animation) -> String {
    let mut root = json::Root {
        asset: json::Asset {
            generator: Some(format!("lagrange {}", env!("CARGO_PKG_VERSION"))),
            ..Default::default()
        },
        ..Default::default()
    };
    let buffer = root.push(json::Buffer {
        byte_length: USize64(0),
        name: None,
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    let mut b = Builder {
        root,
        bytes: Vec::new(),
        buffer,
    };
    let t0 = anim.times[0];
    let times: Vec<f32> = anim.times.iter().map(|t| (t - t0) as f32).collect();
    let time_bytes: Vec<u8> = times.iter().flat_map(|x| x.to_le_bytes()).collect();
    let last = times.last().copied().unwrap_or(0.0);
    let input = b.accessor(
        &time_bytes,
        times.len(),
        json::accessor::ComponentType::F32,
        json::accessor::Type::Scalar,
        None,
        Some((serde_json::json!([0.0]), serde_json::json!([last]))),
    );
    let first = &anim.scenes[0];
    let mut children = Vec::new();
    let mut channels = Vec::new();
    let mut samplers = Vec::new();
    for (i, shape) in first.shapes.iter().enumerate() {
        let color = shape.color;
        let base = [linear(color.r), linear(color.g), linear(color.b), 1.0];
        let material = b.root.push(json::Material {
            name: Some(shape.name.clone()),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor(base),
                metallic_factor: json::material::StrengthFactor(0.1),
                roughness_factor: json::material::StrengthFactor(0.6),
                ..Default::default()
            },
            double_sided: !is_mesh(&shape.geometry),
            ..Default::default()
        });
        let primitive = b.primitive(anim, i, material);
        let mesh = b.root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(shape.name.clone()),
            primitives: vec![primitive],
            weights: None,
        });
        let is_trace = matches!(shape.geometry, Geometry::Trace);
        // The kind, for the page, and the name as written (three.js turns spaces in node names
        // into underscores).
        let extras = serde_json::json!({
            "lagrange_kind": shape.geometry.kind(),
            "lagrange_name": shape.name,
        });
        let node = b.root.push(json::Node {
            mesh: Some(mesh),
            name: Some(shape.name.clone()),
            translation: (!is_trace).then(|| shape.position.map(|x| x as f32).into()),
            rotation: (!is_trace).then(|| {
                let q = quaternion(&shape.rotation);
                json::scene::UnitQuaternion([q.i as f32, q.j as f32, q.k as f32, q.w as f32])
            }),
            extras: serde_json::value::to_raw_value(&extras).ok(),
            ..Default::default()
        });
        children.push(node);
        if is_trace {
            continue;
        }
        b.keyframes(anim, i, (input, node), (&mut samplers, &mut channels));
    }
    let up = anim.up;
    let model = b.root.push(json::Node {
        name: Some("model".to_owned()),
        rotation: Some(json::scene::UnitQuaternion([
            up.i as f32,
            up.j as f32,
            up.k as f32,
            up.w as f32,
        ])),
        children: Some(children),
        ..Default::default()
    });
    let camera_node = b.camera(anim);
    if !channels.is_empty() {
        b.root.push(json::Animation {
            extensions: None,
            extras: Default::default(),
            channels,
            name: Some("run".to_owned()),
            samplers,
        });
    }
    let scene = b.root.push(json::Scene {
        extensions: None,
        extras: scene_extras(anim),
        name: Some(anim.title.clone()),
        nodes: vec![model, camera_node],
    });
    b.root.scene = Some(scene);
    while !b.bytes.len().is_multiple_of(4) {
        b.bytes.push(0);
    }
    let data = base64::engine::general_purpose::STANDARD.encode(&b.bytes);
    b.root.buffers[0] = json::Buffer {
        byte_length: USize64::from(b.bytes.len()),
        name: None,
        uri: Some(format!("data:application/octet-stream;base64,{data}")),
        extensions: None,
        extras: Default::default(),
    };
    // Serializing plain data (numbers, strings, maps) cannot fail.
    b.root.to_string().unwrap_or_default()
}

/// The orientation of a glTF camera (looking down its −z, y up) at `eye` looking at `target`.
fn look_at(eye: [f64; 3], target: [f64; 3]) -> UnitQuaternion<f64> {
    let (eye, target) = (
        nalgebra::Vector3::from(eye),
        nalgebra::Vector3::from(target),
    );
    let back = (eye - target).normalize();
    let right = nalgebra::Vector3::y().cross(&back).normalize();
    let up = back.cross(&right);
    quaternion(&nalgebra::Matrix3::from_columns(&[right, up, back]))
}
