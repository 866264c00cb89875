//! Recording a run to [rerun](https://rerun.io) (feature `rerun`).
//!
//! [`RerunLogger`] is an [`Observer`]: call [`Observer::record`] after every frame (or
//! substep) and [`Observer::finish`] at the end. It writes a `.rrd` file
//! ([`RerunLogger::save`]), streams to a viewer it spawns ([`RerunLogger::spawn`]) or one that
//! listens already ([`RerunLogger::connect`]), or keeps everything in memory
//! ([`RerunLogger::memory`]). Open a file with `rerun FILE.rrd`.
//!
//! # Timeline
//!
//! `sim_time`: the simulation time \[s\] passed to `record` (a duration timeline).
//!
//! # Entity paths
//!
//! Names are those of the bodies ([`RerunLogger::with_body_names`], e.g. the URDF links of
//! [`crate::io::robot::UrdfRobotHandles::body_names`]; `body<index>` otherwise) and of the joints;
//! characters other than `A-Z a-z 0-9 _ -` become `_`.
//!
//! | path | archetype | when | content |
//! |---|---|---|---|
//! | `world/bodies/<body>` | `Transform3D` | every record | body pose (world) \[m\] |
//! | `world/bodies/<body>/collider<i>` | `Boxes3D` / `Ellipsoids3D` / `Capsules3D` / `Cylinders3D` / `Mesh3D` | once, static | collider shape in the body frame (meshes and convex hulls as triangles; other shapes: their local bounding box) |
//! | `world/bodies/<body>/visual<i>` | `Mesh3D` | once, static | URDF `<visual>` meshes ([`RerunLogger::with_visual_meshes`]) in the body frame |
//! | `world/static/collider<i>` | same | once, static | colliders without a body |
//! | `world/joints/<joint>/axes` | `Arrows3D` | every record | joint frame x (red), y (green), z (blue) at anchor 1 |
//! | `world/joints/<joint>/anchors` | `Points3D` | every record | anchor 1 and anchor 2 \[m\] |
//! | `joints/<joint>/<dof>/q` | `Scalars` | every record | displacement \[m\] or angle \[rad\] |
//! | `joints/<joint>/<dof>/q/stop_min`, `…/q/stop_max` | `Scalars` | free DOFs with stops | the stops `SD-`, `SD+` [m, rad] (those set; a coupled stop's radius bounds each component), drawn as lines beside `q` |
//! | `joints/<joint>/<dof>/rate` | `Scalars` | free DOFs | rate [m/s, rad/s] |
//! | `joints/<joint>/<dof>/force` | `Scalars` | every record | the **law's** total force/moment `F(q, q̇)` [N, N·m] (CSV `FX .. MZ`); on a DOF stiffer than the substep resolves it is `K·q` on a `q` near f32 resolution, not what the joint carries |
//! | `joints/<joint>/<dof>/force/{elastic,damping,friction,stop,sensor,motor}` | `Scalars` | free DOFs (`motor` where the DOF has one) | the law's total split by source [N, N·m] |
//! | `joints/<joint>/<dof>/applied` | `Scalars` | every record | force/moment the joint **transmitted** to its bodies over the substep, `−P/h` of the implicit update [N, N·m] (CSV `AFX .. AMZ`; the summary's peaks) |
//! | `joints/<joint>/<dof>/slip` | `Scalars` | free DOFs with friction | 1 slipping, 0 sticking |
//! | `joints/<joint>/<dof>/stop` | `Scalars` | free DOFs with stops | −1 beyond `SD-`, +1 beyond `SD+` (or the coupled radius), 0 inside |
//! | `joints/<joint>/locked` | `Scalars` | every record | 1 once the sensor lock is on, else 0 |
//! | `joints/<joint>/energy/{elastic,damping,friction,stop,numerical,internal}` | `Scalars` | every record | energies \[J\]: stored (blocked DOFs at the realised stiffness), dissipated by viscosity and critical damping, by friction, by stops, by the numerical damping of unresolved DOFs, and the law's internal energy (as the CSV's `E_*` and `IE`); `motor` too where a motor worked ([`crate::law::JointEnergy::motor`]) |
//! | `joints/<joint>/<law>/<channel>` | `Scalars` | joints with a connector law | its readout, `law` = `planar_friction`, `joint_friction` or `flex_joint` ([`crate::law::ConnectorReport::channels`]) |
//! | `warnings` | `TextLog` (level INFO for notices, WARN for warnings) | on health events | `notice: joint <name> at t = <t> s: …`, `warning: joint <name> at t = <t> s: …` (`dynamics::health`) |
//! | `events` | `TextLog` | on events | `sensor <id> at t = <t> s: <reason>`, `joint <name> at t = <t> s: flex joint switched to the dynamic phase (...)` |
//!
//! `<dof>` is `dx dy dz rx ry rz`; the blocked DOFs are logged (`q`, `force`, `applied`:
//! the penalty deflection and the reaction) unless [`RerunLogger::free_dofs_only`] is set.
//! The values are those of [`crate::JointState`] after the last substep.
//!
//! # Blueprint
//!
//! At the first record, once the joints are known, the logger sends a blueprint (the
//! viewer's layout, [`RerunLogger::blueprint`]; off with [`RerunLogger::with_blueprint`]) so
//! that the recording opens on plots rather than on the viewer's guess:
//!
//! - left: a 3-D view of `world` (bodies, colliders, joint frames), above a text-log view of
//!   `events` and `warnings`;
//! - right: one tab per joint (named after it), a column of time-series views
//!   ([`RerunLogger::joint_views`]), all with the origin `joints/<joint>`:
//!   1. force \[N\] and moment [N·m]: the transmitted `applied` of every logged DOF, and the
//!      law's total and parts `force/**` of the free DOFs;
//!   2. `q/**` of every logged DOF: the displacement [m, rad] with its stop lines;
//!   3. `energy/**` \[J\];
//!   4. the states: `slip` and `stop` of the free DOFs, `locked`;
//!   5. with a connector law, its readout `<law>/**`.
//!
//! Entities in no view (`rate`, the blocked DOFs' law force) stay in the viewer's entity
//! tree, from where they can be dragged into a view.
//!
//! The blueprint travels in the recording itself, as a second store (kind blueprint, same
//! application id) followed by the command that activates it: a `.rrd` written by
//! [`RerunLogger::save`] holds it, and `rerun FILE.rrd` opens on it; no sibling `.rbl` file
//! is written. A viewer that streams ([`RerunLogger::spawn`], [`RerunLogger::connect`])
//! receives it the same way. It is activated and made the application's default blueprint
//! (rerun's `make_active`, `make_default`).
//!
//! Rerun uses its own `glam`; everything is handed over as plain arrays.

use super::{Observer, OutputError};
use crate::dynamics::{JointState, Kjoint, KjointEvent, KjointSet, Severity};
use crate::law::{Dof, JointEnergy};
use crate::rapier::dynamics::RigidBodyHandle;
use crate::rapier::geometry::{Collider, TypedShape};
use crate::rapier::math::{Pose, Real, Rotation, Vector};
use crate::rapier::pipeline::PhysicsWorld;
use rerun::datatypes::Quaternion;
use rerun::{RecordingStream, RecordingStreamBuilder};
use std::collections::HashMap;
use std::path::Path;

/// Application id of the recordings.
pub const APP_ID: &str = "rapier_kjoint";

/// A time-series view of the blueprint: its title and its contents (rerun query
/// expressions, `+ /path` for one entity, `+ /path/**` for it and everything below).
#[derive(Debug, Clone, PartialEq)]
pub struct PlotView {
    /// Title, with the units.
    pub title: String,
    /// Query expressions.
    pub contents: Vec<String>,
}

/// An [`Observer`] that logs bodies, joints and events to a rerun recording (module docs).
pub struct RerunLogger {
    rec: RecordingStream,
    body_names: HashMap<RigidBodyHandle, String>,
    free_only: bool,
    axis_length: f32,
    shapes_logged: bool,
    /// Send the blueprint ([`RerunLogger::blueprint`]) at the first record.
    send_blueprint: bool,
    blueprint_sent: bool,
    /// Visual meshes to log once: (body, vertices in the body frame, triangles).
    visuals: Vec<(RigidBodyHandle, Vec<[f32; 3]>, Vec<[u32; 3]>)>,
}

fn rec_err(e: impl std::fmt::Display) -> OutputError {
    OutputError::Recording(e.to_string())
}

/// `name` with every character other than `A-Z a-z 0-9 _ -` replaced by `_`.
pub fn entity_name(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() {
        "_".into()
    } else {
        s
    }
}

// rerun stores f32: rapier's values (f64 with the `f64` feature) are converted here, for
// drawing only (the casts are the identity in f32).
#[allow(clippy::unnecessary_cast)]
fn quat(r: Rotation) -> Quaternion {
    Quaternion::from_xyzw([r.x as f32, r.y as f32, r.z as f32, r.w as f32])
}

#[allow(clippy::unnecessary_cast)]
fn arr(v: Vector) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

#[allow(clippy::unnecessary_cast)]
fn real(x: Real) -> f32 {
    x as f32
}

impl RerunLogger {
    /// Wraps an existing recording stream.
    pub fn from_stream(rec: RecordingStream) -> Self {
        RerunLogger {
            rec,
            body_names: HashMap::new(),
            free_only: false,
            axis_length: 0.1,
            shapes_logged: false,
            send_blueprint: true,
            blueprint_sent: false,
            visuals: Vec::new(),
        }
    }

    /// Records to the `.rrd` file `path`.
    pub fn save(path: impl AsRef<Path>) -> Result<Self, OutputError> {
        let rec = RecordingStreamBuilder::new(APP_ID)
            .save(path.as_ref())
            .map_err(|e| OutputError::Recording(format!("{}: {e}", path.as_ref().display())))?;
        Ok(Self::from_stream(rec))
    }

    /// Spawns a rerun viewer (the `rerun` executable must be on the `PATH`) and streams to it.
    pub fn spawn() -> Result<Self, OutputError> {
        let rec = RecordingStreamBuilder::new(APP_ID)
            .spawn()
            .map_err(rec_err)?;
        Ok(Self::from_stream(rec))
    }

    /// Streams to a viewer that is already running: `url` like
    /// `rerun+http://127.0.0.1:9876/proxy`, `None` for the default local viewer.
    pub fn connect(url: Option<&str>) -> Result<Self, OutputError> {
        let b = RecordingStreamBuilder::new(APP_ID);
        let rec = match url {
            Some(u) => b.connect_grpc_opts(u.to_string()),
            None => b.connect_grpc(),
        }
        .map_err(rec_err)?;
        Ok(Self::from_stream(rec))
    }

    /// Keeps the recording in memory (for benchmarks and tests); the storage holds the data.
    pub fn memory() -> Result<(Self, rerun::sink::MemorySinkStorage), OutputError> {
        let (rec, storage) = RecordingStreamBuilder::new(APP_ID)
            .memory()
            .map_err(rec_err)?;
        Ok((Self::from_stream(rec), storage))
    }

    /// Names of the bodies in entity paths (others are `body<index>`).
    #[must_use]
    pub fn with_body_names(mut self, names: HashMap<RigidBodyHandle, String>) -> Self {
        self.body_names = names;
        self
    }

    /// Draws these URDF `<visual>` meshes ([`crate::io::robot::UrdfRobotHandles::visual_meshes`]) on
    /// their bodies, as `world/bodies/<body>/visual<i>`.
    #[must_use]
    pub fn with_visual_meshes(mut self, meshes: &[crate::io::visual::VisualMesh]) -> Self {
        self.visuals = meshes
            .iter()
            .map(|m| (m.body, m.vertices.clone(), m.triangles.clone()))
            .collect();
        self
    }

    /// Names the bodies after the robot's links and draws its visual meshes
    /// ([`Self::with_body_names`] and [`Self::with_visual_meshes`]).
    #[must_use]
    pub fn with_urdf_robot(self, robot: &crate::io::robot::UrdfRobotHandles) -> Self {
        self.with_body_names(robot.body_names())
            .with_visual_meshes(&robot.visual_meshes)
    }

    /// Logs only the free DOFs of each joint.
    #[must_use]
    pub fn free_dofs_only(mut self, yes: bool) -> Self {
        self.free_only = yes;
        self
    }

    /// Length of the joint-axis arrows \[m\] (default 0.1 m).
    #[must_use]
    pub fn with_axis_length(mut self, length: f32) -> Self {
        self.axis_length = length;
        self
    }

    /// The underlying stream (to log more data alongside).
    pub fn stream(&self) -> &RecordingStream {
        &self.rec
    }

    /// Whether to send [`Self::blueprint`] at the first record (default `true`); `false`
    /// leaves the layout to the viewer's heuristics or to a blueprint of your own.
    #[must_use]
    pub fn with_blueprint(mut self, yes: bool) -> Self {
        self.send_blueprint = yes;
        self
    }

    /// The layout the recording opens on (module docs, "Blueprint"): the 3-D view and the
    /// event log on the left, one tab per joint on the right with its time series.
    pub fn blueprint(&self, joints: &KjointSet) -> rerun::blueprint::Blueprint {
        use rerun::blueprint::{
            Blueprint, ContainerLike, Horizontal, Spatial3DView, Tabs, TextLogView, TimeSeriesView,
            Vertical,
        };
        let tabs: Vec<ContainerLike> = joints
            .iter()
            .map(|(_, j)| {
                let views: Vec<ContainerLike> = self
                    .joint_views(j)
                    .into_iter()
                    .map(|v| {
                        TimeSeriesView::new(v.title)
                            .with_origin(format!("/joints/{}", entity_name(&j.name)))
                            .with_contents(v.contents)
                            .into()
                    })
                    .collect();
                Vertical::new(views).with_name(j.name.clone()).into()
            })
            .collect();
        let left = Vertical::new([
            Spatial3DView::new("bodies and joints")
                .with_origin("/world")
                .into(),
            TextLogView::new("events and warnings")
                .with_contents(["+ /events", "+ /warnings"])
                .into(),
        ])
        .with_row_shares([0.75, 0.25]);
        let mut columns: Vec<ContainerLike> = vec![left.into()];
        if !tabs.is_empty() {
            columns.push(Tabs::new(tabs).with_name("joints").into());
        }
        Blueprint::new(Horizontal::new(columns)).with_auto_views(false)
    }

    /// The time-series views of joint `j` (module docs, "Blueprint").
    pub fn joint_views(&self, j: &crate::dynamics::Kjoint) -> Vec<PlotView> {
        let base = format!("/joints/{}", entity_name(&j.name));
        let jt = j.property.joint_type;
        let logged: Vec<Dof> = Dof::ALL
            .into_iter()
            .filter(|d| !self.free_only || jt.is_free(*d))
            .collect();
        let free = || logged.iter().filter(|d| jt.is_free(**d));
        let dof = |d: &Dof| format!("{base}/{}", d.name());
        let mut force: Vec<String> = logged
            .iter()
            .map(|d| format!("+ {}/applied", dof(d)))
            .collect();
        force.extend(free().map(|d| format!("+ {}/force/**", dof(d))));
        // as logged: slip with friction, stop with stops
        let mut state: Vec<String> = Vec::new();
        for d in free() {
            let law = j.property.dof(*d);
            if law.friction_active() {
                state.push(format!("+ {}/slip", dof(d)));
            }
            if law.has_stops() {
                state.push(format!("+ {}/stop", dof(d)));
            }
        }
        state.push(format!("+ {base}/locked"));
        let mut views = vec![
            PlotView {
                title: format!("{}: force [N] and moment [N·m]", j.name),
                contents: force,
            },
            PlotView {
                title: format!("{}: q [m, rad] and its stops", j.name),
                contents: logged
                    .iter()
                    .map(|d| format!("+ {}/q/**", dof(d)))
                    .collect(),
            },
            PlotView {
                title: format!("{}: energy [J]", j.name),
                contents: vec![format!("+ {base}/energy/**")],
            },
            PlotView {
                title: format!("{}: slip, stop contact, lock", j.name),
                contents: state,
            },
        ];
        let connector = match j.connector_law() {
            crate::law::ConnectorLaw::None => None,
            crate::law::ConnectorLaw::PlanarFriction(_) => Some("planar_friction"),
            crate::law::ConnectorLaw::FlexJoint(_) => Some("flex_joint"),
            crate::law::ConnectorLaw::JointFriction(_) => Some("joint_friction"),
        };
        if let Some(law) = connector {
            views.push(PlotView {
                title: format!("{}: {law}", j.name),
                contents: vec![format!("+ {base}/{law}/**")],
            });
        }
        views
    }

    fn body_name(&self, h: RigidBodyHandle) -> String {
        match self.body_names.get(&h) {
            Some(n) => entity_name(n),
            None => format!("body{}", h.into_raw_parts().0),
        }
    }

    fn scalar(&self, path: &str, v: f64) -> Result<(), OutputError> {
        self.rec
            .log(path, &rerun::Scalars::new([v]))
            .map_err(rec_err)
    }

    fn log_shape(&self, path: &str, c: &Collider, local: Pose) -> Result<(), OutputError> {
        let t = arr(local.translation);
        let r = local.rotation;
        let res = match c.shape().as_typed_shape() {
            TypedShape::Cuboid(b) => self.rec.log_static(
                path,
                &rerun::Boxes3D::from_centers_and_half_sizes([t], [arr(b.half_extents)])
                    .with_quaternions([quat(r)]),
            ),
            TypedShape::Ball(b) => self.rec.log_static(
                path,
                &rerun::Ellipsoids3D::from_centers_and_radii([t], [real(b.radius)]),
            ),
            TypedShape::Capsule(cap) => {
                let a = local.transform_point(cap.segment.a);
                let b = local.transform_point(cap.segment.b);
                let d = b - a;
                let len = d.length();
                let q = if len > 0.0 {
                    Rotation::from_rotation_arc(Vector::Z, d / len)
                } else {
                    Rotation::IDENTITY
                };
                self.rec.log_static(
                    path,
                    &rerun::Capsules3D::from_lengths_and_radii([real(len)], [real(cap.radius)])
                        .with_translations([arr(a)])
                        .with_quaternions([quat(q)]),
                )
            }
            TypedShape::Cylinder(cyl) => {
                // parry's cylinders run along y, rerun's along z
                let q = r * Rotation::from_rotation_arc(Vector::Z, Vector::Y);
                self.rec.log_static(
                    path,
                    &rerun::Cylinders3D::from_lengths_and_radii(
                        [real(2.0 * cyl.half_height)],
                        [real(cyl.radius)],
                    )
                    .with_centers([t])
                    .with_quaternions([quat(q)]),
                )
            }
            TypedShape::TriMesh(m) => {
                let v: Vec<[f32; 3]> = m
                    .vertices()
                    .iter()
                    .map(|p| arr(local.transform_point(*p)))
                    .collect();
                self.rec.log_static(
                    path,
                    &rerun::Mesh3D::new(v).with_triangle_indices(m.indices().iter().copied()),
                )
            }
            TypedShape::ConvexPolyhedron(h) => {
                let (pts, tris) = h.to_trimesh();
                let v: Vec<[f32; 3]> = pts.iter().map(|p| arr(local.transform_point(*p))).collect();
                self.rec
                    .log_static(path, &rerun::Mesh3D::new(v).with_triangle_indices(tris))
            }
            _ => {
                let aabb = c.shape().compute_local_aabb();
                let center = local.transform_point((aabb.mins + aabb.maxs) * 0.5);
                self.rec.log_static(
                    path,
                    &rerun::Boxes3D::from_centers_and_half_sizes(
                        [arr(center)],
                        [arr((aabb.maxs - aabb.mins) * 0.5)],
                    )
                    .with_quaternions([quat(r)]),
                )
            }
        };
        res.map_err(rec_err)
    }

    fn log_shapes(&self, world: &PhysicsWorld) -> Result<(), OutputError> {
        for (i, (b, vertices, triangles)) in self.visuals.iter().enumerate() {
            let path = format!("world/bodies/{}/visual{i}", self.body_name(*b));
            self.rec
                .log_static(
                    path,
                    &rerun::Mesh3D::new(vertices.iter().copied())
                        .with_triangle_indices(triangles.iter().copied()),
                )
                .map_err(rec_err)?;
        }
        for (ch, c) in world.colliders.iter() {
            let i = ch.into_raw_parts().0;
            match (c.parent(), c.position_wrt_parent()) {
                (Some(b), Some(local)) => {
                    let path = format!("world/bodies/{}/collider{i}", self.body_name(b));
                    self.log_shape(&path, c, *local)?;
                }
                _ => {
                    let path = format!("world/static/collider{i}");
                    self.log_shape(&path, c, *c.position())?;
                }
            }
        }
        Ok(())
    }
}

impl RerunLogger {
    /// Once: the blueprint (unless switched off) and the static shapes.
    fn log_once(&mut self, world: &PhysicsWorld, joints: &KjointSet) -> Result<(), OutputError> {
        if self.send_blueprint && !self.blueprint_sent {
            let activation = rerun::blueprint::BlueprintActivation {
                make_active: true,
                make_default: true,
            };
            self.blueprint(joints)
                .send(&self.rec, activation)
                .map_err(rec_err)?;
            self.blueprint_sent = true;
        }
        if !self.shapes_logged {
            self.log_shapes(world)?;
            self.shapes_logged = true;
        }
        Ok(())
    }

    /// The pose of every body under `world/bodies/<body>`.
    fn log_bodies(&self, world: &PhysicsWorld) -> Result<(), OutputError> {
        for (h, b) in world.bodies.iter() {
            let p = b.position();
            self.rec
                .log(
                    format!("world/bodies/{}", self.body_name(h)),
                    &rerun::Transform3D::from_translation_rotation(
                        arr(p.translation),
                        quat(p.rotation),
                    ),
                )
                .map_err(rec_err)?;
        }
        Ok(())
    }

    /// The joint frame's axes at anchor 1 and the two anchors, under `world/joints/<name>`.
    fn log_joint_frame(&self, name: &str, s: &JointState) -> Result<(), OutputError> {
        let fq = s.frame;
        let frame = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            fq[3], fq[0], fq[1], fq[2],
        ));
        let l = self.axis_length as f64;
        let axes: Vec<[f32; 3]> = [
            nalgebra::Vector3::x(),
            nalgebra::Vector3::y(),
            nalgebra::Vector3::z(),
        ]
        .iter()
        .map(|e| {
            let v = frame * e * l;
            [v.x as f32, v.y as f32, v.z as f32]
        })
        .collect();
        let a1 = s.anchor1.map(|v| v as f32);
        let a2 = s.anchor2.map(|v| v as f32);
        self.rec
            .log(
                format!("world/joints/{name}/axes"),
                &rerun::Arrows3D::from_vectors(axes)
                    .with_origins([a1, a1, a1])
                    .with_colors([
                        rerun::Color::from_rgb(230, 40, 40),
                        rerun::Color::from_rgb(40, 200, 40),
                        rerun::Color::from_rgb(40, 80, 230),
                    ]),
            )
            .map_err(rec_err)?;
        self.rec
            .log(
                format!("world/joints/{name}/anchors"),
                &rerun::Points3D::new([a1, a2]).with_radii([0.01]),
            )
            .map_err(rec_err)?;
        Ok(())
    }

    /// The per-DOF channels of joint `j` under `joints/<name>/<dof>`: q, force, applied on
    /// every DOF (free only with `free_only`); rate, force parts, slip, stops and stop status
    /// on free ones.
    fn log_joint_dofs(&self, name: &str, j: &Kjoint, s: &JointState) -> Result<(), OutputError> {
        let jt = j.property.joint_type;
        for dof in Dof::ALL {
            let free = jt.is_free(dof);
            if !free && self.free_only {
                continue;
            }
            let i = dof.index();
            let base = format!("joints/{name}/{}", dof.name());
            self.scalar(&format!("{base}/q"), s.q[i])?;
            self.scalar(&format!("{base}/force"), s.force[i])?;
            self.scalar(&format!("{base}/applied"), s.applied[i])?;
            if !free {
                continue;
            }
            self.scalar(&format!("{base}/rate"), s.rate[i])?;
            let p = &s.parts[i];
            for (n, v) in [
                ("elastic", p.elastic),
                ("damping", p.damping),
                ("friction", p.friction),
                ("stop", p.stop),
                ("sensor", p.sensor),
            ] {
                self.scalar(&format!("{base}/force/{n}"), v)?;
            }
            if j.motor(dof).is_some() {
                self.scalar(&format!("{base}/force/motor"), p.motor)?;
            }
            let law = j.property.dof(dof);
            if law.friction_active() {
                self.scalar(&format!("{base}/slip"), s.status[i].friction.code())?;
            }
            if law.has_stops() {
                for (n, v) in [("stop_min", law.stop_min), ("stop_max", law.stop_max)] {
                    if v != 0.0 {
                        self.scalar(&format!("{base}/q/{n}"), v)?;
                    }
                }
                self.scalar(&format!("{base}/stop"), s.status[i].stop.code())?;
            }
        }
        Ok(())
    }

    /// The joint's lock, energies and connector channels under `joints/<name>`.
    fn log_joint_totals(
        &self,
        name: &str,
        s: &JointState,
        e: &JointEnergy,
    ) -> Result<(), OutputError> {
        self.scalar(
            &format!("joints/{name}/locked"),
            if s.locked { 1.0 } else { 0.0 },
        )?;
        for (n, v) in [
            ("elastic", e.elastic),
            ("damping", e.damping),
            ("friction", e.friction),
            ("stop", e.stop),
            ("numerical", e.numerical),
            ("internal", e.internal),
        ] {
            self.scalar(&format!("joints/{name}/energy/{n}"), v)?;
        }
        // the rotors' kinetic energy, where the joint has an armature
        if e.kinetic != 0.0 {
            self.scalar(&format!("joints/{name}/energy/kinetic"), e.kinetic)?;
        }
        // the motors' book, where one worked
        if e.motor != 0.0 {
            self.scalar(&format!("joints/{name}/energy/motor"), e.motor)?;
        }
        if let Some(c) = &s.connector {
            let (law, ch) = c.channels();
            for (n, v) in ch {
                self.scalar(&format!("joints/{name}/{law}/{n}"), v)?;
            }
        }
        Ok(())
    }

    /// The events as text logs: what happened in the model under `events`, the health of
    /// the run (notices, warnings) under `warnings`, at its level.
    fn log_events(&self, events: &[KjointEvent]) -> Result<(), OutputError> {
        for ev in events {
            let (entity, level) = match ev.severity() {
                Severity::Info => ("events", rerun::TextLogLevel::INFO),
                Severity::Notice => ("warnings", rerun::TextLogLevel::INFO),
                Severity::Warning => ("warnings", rerun::TextLogLevel::WARN),
            };
            self.rec
                .log(
                    entity,
                    &rerun::TextLog::new(ev.to_string()).with_level(level),
                )
                .map_err(rec_err)?;
        }
        Ok(())
    }
}

impl Observer for RerunLogger {
    fn record(
        &mut self,
        time: f64,
        world: &PhysicsWorld,
        joints: &KjointSet,
        events: &[KjointEvent],
    ) -> Result<(), OutputError> {
        self.rec.set_duration_secs("sim_time", time.max(0.0));
        self.log_once(world, joints)?;
        self.log_bodies(world)?;
        for (_, j) in joints.iter() {
            let Some(s) = j.state() else { continue };
            let name = entity_name(&j.name);
            self.log_joint_frame(&name, s)?;
            self.log_joint_dofs(&name, j, s)?;
            self.log_joint_totals(&name, s, &j.closed_energy(&world.bodies))?;
        }
        self.log_events(events)
    }

    /// The events since the last record, the failing substep's included, as text logs,
    /// each at its own time.
    fn failed(&mut self, events: &[KjointEvent]) -> Result<(), OutputError> {
        for ev in events {
            self.rec.set_duration_secs("sim_time", ev.time.max(0.0));
            self.log_events(std::slice::from_ref(ev))?;
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        self.rec.flush_blocking().map_err(rec_err)?;
        Ok(())
    }
}
