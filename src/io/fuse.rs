//! Fusing the links joined by fixed joints into one rigid body
//! ([`UrdfOptions::fuse_fixed_joints`]), for URDF and MJCF alike, on the
//! [`RobotDescription`] before it is inserted.
//!
//! A KJOINT2 fixed joint is a penalty joint: its blocked DOFs move by `F·h²/m` under a load
//! `F` that acts after the joint solve (about `0.4·F·h²/m` along gravity where the contact
//! holds the link, which the solve takes as heavier there; rapier's contact friction on a
//! light foot turns it by `τ·h²/I`, 0.3 rad per substep for go1's 60 g feet at 240 Hz). Fused, the link is part of
//! its parent's body and nothing can move it against it: MuJoCo's `fusestatic` (its default
//! for URDF), PyBullet's and Isaac's "merge fixed links".
//!
//! A fixed joint `P → C` is fused when the option is on, the child's body is dynamic, no
//! per-joint override names it (the user wants that joint: its readout, a break criterion,
//! a rapier engine) and it has neither a break criterion nor a connector law. The child's
//! colliders (their poses re-expressed in the parent's frame), visual meshes (triangles
//! moved) and mass properties (mass, centre of mass and inertia, added to the parent's by the
//! parallel axis theorem in double precision, then placed on the body as the loaders do,
//! [`crate::io::urdf::place_mass`]) go to the parent; every other joint on the child is
//! attached to the parent with its anchors (and a rapier joint's frames) re-expressed in the
//! parent's frame (KJOINT2 frames are world frames: unchanged). Chains fuse transitively. A
//! child of a fixed body (a fixed root, the world) becomes part of that fixed body: it was
//! held there by a penalty joint, it is now exactly there.

use crate::dynamics::{from_quat, from_vec3, to_quat, to_vec3};
use crate::io::robot::{FusedLink, RobotDescription, RobotJointKind};
use crate::io::urdf::{place_mass, LinkMass, UrdfOptions};
use crate::law::JointType;
use crate::rapier::dynamics::{MassProperties, RigidBodyAdditionalMassProps};
use crate::rapier::math::Pose;
use nalgebra::{Isometry3, Matrix3, Translation3};

/// A pose in f64 (nalgebra).
fn iso(p: &Pose) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::from(from_vec3(p.translation)),
        from_quat(p.rotation),
    )
}

/// An f64 pose back in rapier's.
fn pose(i: &Isometry3<f64>) -> Pose {
    Pose::from_parts(to_vec3(&i.translation.vector), to_quat(&i.rotation))
}

/// Rapier's mass properties `mp`, moved by `at` (their frame in the wanted one), in f64.
fn mass_of(mp: &MassProperties, at: &Isometry3<f64>) -> LinkMass {
    let i = mp.reconstruct_inertia_matrix();
    let local = Matrix3::from_fn(|r, k| i.col(k)[r] as f64);
    let rot = at.rotation.to_rotation_matrix();
    LinkMass {
        m: mp.mass() as f64,
        c: at.transform_point(&from_vec3(mp.local_com).into()).coords,
        inertia: rot.matrix() * local * rot.matrix().transpose(),
    }
}

/// The mass of a link as rapier makes it from its colliders and its body's own properties,
/// in the frame `at` of the link in the wanted one.
fn link_mass(link: &crate::io::robot::RobotLink, at: &Isometry3<f64>) -> LinkMass {
    let mut sum = LinkMass::ZERO;
    for c in &link.colliders {
        let p = c.position_wrt_parent().copied().unwrap_or(*c.position());
        sum = sum.add(mass_of(&c.mass_properties(), &(at * iso(&p))));
    }
    let own = link
        .body
        .mass_properties()
        .additional_local_mprops
        .as_deref();
    if let Some(RigidBodyAdditionalMassProps::MassProps(m)) = own {
        sum = sum.add(mass_of(m, at));
    }
    sum
}

impl<Format> RobotDescription<Format> {
    /// Fuses the links joined by fixed joints into one body (module docs of
    /// [`crate::io::fuse`]), unless `options.fuse_fixed_joints` is off; adds a notice naming
    /// the fused joints.
    pub(crate) fn fuse_fixed_joints(&mut self, options: &UrdfOptions) {
        if !options.fuse_fixed_joints {
            return;
        }
        let n = self.links.len();
        // the fused joint into each child link
        let mut parent: Vec<Option<usize>> = vec![None; n];
        let mut fused_joint = vec![false; self.joints.len()];
        for (k, j) in self.joints.iter().enumerate() {
            let RobotJointKind::Kjoint(d) = &j.kind else {
                continue;
            };
            let named = j.names.iter().any(|name| options.joints.contains_key(name));
            let child_dynamic = self.links.get(j.link2).is_some_and(|l| l.body.is_dynamic());
            if d.property.joint_type != JointType::Fixed
                || named
                || d.break_criterion.is_some()
                || !matches!(d.connector, crate::law::ConnectorLaw::None)
                || !child_dynamic
                || j.link1 == j.link2
                || j.link1 >= n
                || parent[j.link2].is_some()
            {
                continue;
            }
            parent[j.link2] = Some(j.link1);
            fused_joint[k] = true;
        }
        if !fused_joint.contains(&true) {
            return;
        }
        // each link's target (the end of its chain of fused joints; a loop is not followed)
        let target = |mut l: usize| {
            let mut steps = 0;
            while let Some(p) = parent[l] {
                l = p;
                steps += 1;
                if steps > n {
                    break;
                }
            }
            l
        };
        let targets: Vec<usize> = (0..n).map(target).collect();
        let poses: Vec<Isometry3<f64>> =
            self.links.iter().map(|l| iso(l.body.position())).collect();
        // each link's frame in its target's
        let rel: Vec<Isometry3<f64>> = (0..n)
            .map(|l| poses[targets[l]].inverse() * poses[l])
            .collect();
        // the masses of the groups, in their targets' frames (before the colliders move)
        let mut masses = vec![LinkMass::ZERO; n];
        let mut grouped = vec![false; n];
        for l in 0..n {
            masses[targets[l]] = masses[targets[l]].add(link_mass(&self.links[l], &rel[l]));
            if targets[l] != l {
                grouped[targets[l]] = true;
            }
        }
        // the joints: the fused ones removed, the others re-attached
        let mut notes = Vec::new();
        let mut fused = Vec::new();
        let mut kept = Vec::with_capacity(self.joints.len());
        for (k, mut j) in std::mem::take(&mut self.joints).into_iter().enumerate() {
            if fused_joint[k] {
                let (c, p) = (j.link2, targets[j.link1]);
                notes.push(format!(
                    "{} ({} → {})",
                    j.names[0], self.links[c].name, self.links[p].name
                ));
                fused.push((j.names, c));
                continue;
            }
            let (r1, r2) = (rel[j.link1], rel[j.link2]);
            match &mut j.kind {
                RobotJointKind::Kjoint(d) => {
                    let a1 = r1.transform_point(&from_vec3(d.local_anchor1).into());
                    let a2 = r2.transform_point(&from_vec3(d.local_anchor2).into());
                    d.local_anchor1 = to_vec3(&a1.coords);
                    d.local_anchor2 = to_vec3(&a2.coords);
                }
                RobotJointKind::Rapier(g) => {
                    g.local_frame1 = pose(&(r1 * iso(&g.local_frame1)));
                    g.local_frame2 = pose(&(r2 * iso(&g.local_frame2)));
                }
            }
            j.link1 = targets[j.link1];
            j.link2 = targets[j.link2];
            kept.push(j);
        }
        // the links: colliders and meshes moved to their targets
        let mut moved = Vec::with_capacity(n);
        let mut ranges = vec![(0usize, 0usize, 0usize); n];
        for l in 0..n {
            let t = targets[l];
            if t == l {
                moved.push(None);
                continue;
            }
            let r = rel[l];
            let link = &mut self.links[l];
            let cols: Vec<_> = std::mem::take(&mut link.colliders)
                .into_iter()
                .map(|mut c| {
                    // (a collider not yet attached keeps its pose in the link as its
                    // position, which `insert_with_parent` takes as its pose in the body;
                    // rapier's `set_position_wrt_parent` does nothing without a parent: the
                    // fused links' colliders stayed at the parent's origin, go1's and the
                    // A1's foot spheres at their knees, a robotics engineer's trial of
                    // 2026-12-06)
                    let moved = |p: &Pose| pose(&(r * iso(p)));
                    match c.position_wrt_parent().copied() {
                        Some(p) => c.set_position_wrt_parent(moved(&p)),
                        None => {
                            let p = *c.position();
                            c.set_position(moved(&p));
                        }
                    }
                    c
                })
                .collect();
            let meshes: Vec<_> = std::mem::take(&mut link.visual_meshes)
                .into_iter()
                .map(|mut m| {
                    for v in &mut m.vertices {
                        let p = r.transform_point(&nalgebra::Point3::new(
                            v[0] as f64,
                            v[1] as f64,
                            v[2] as f64,
                        ));
                        *v = [p.x as f32, p.y as f32, p.z as f32];
                    }
                    m
                })
                .collect();
            moved.push(Some((cols, meshes)));
        }
        for (l, m) in moved.into_iter().enumerate() {
            let t = targets[l];
            if let Some((cols, meshes)) = m {
                let start = self.links[t].colliders.len();
                ranges[l] = (t, start, start + cols.len());
                self.links[t].colliders.extend(cols);
                self.links[t].visual_meshes.extend(meshes);
            }
        }
        for t in 0..n {
            if !grouped[t] || !self.links[t].body.is_dynamic() {
                continue;
            }
            let m = masses[t];
            let link = &mut self.links[t];
            for c in &mut link.colliders {
                c.set_density(0.0);
            }
            let mp = crate::io::urdf::mass_properties(&m.c, m.m, &m.inertia);
            if let Some(err) = place_mass(&mut link.body, &mut link.colliders, mp) {
                self.notices.push(format!(
                    "link `{}`: the colliders of the links fused into it make rapier \
                     diagonalise its inertia tensor again in f32: off by up to {:.1} % of its \
                     largest term",
                    link.name,
                    err * 100.0
                ));
            }
        }
        // the links removed, the joints' indices remapped
        let mut new_index = vec![usize::MAX; n];
        let mut next = 0;
        for l in 0..n {
            if targets[l] == l {
                new_index[l] = next;
                next += 1;
            }
        }
        for j in &mut kept {
            j.link1 = new_index[j.link1];
            j.link2 = new_index[j.link2];
        }
        for (names, c) in fused {
            let (t, start, end) = ranges[c];
            self.fused.push(FusedLink {
                joints: names,
                link: self.links[c].name.clone(),
                into: new_index[t],
                pose: pose(&rel[c]),
                colliders: start..end,
            });
        }
        let mut l = 0;
        self.links.retain(|_| {
            let keep = targets[l] == l;
            l += 1;
            keep
        });
        self.joints = kept;
        self.notices.push(format!(
            "{} fixed joint{} fused into {} parent link{}: {}",
            notes.len(),
            if notes.len() == 1 { "" } else { "s" },
            if notes.len() == 1 { "its" } else { "their" },
            if notes.len() == 1 { "" } else { "s" },
            notes.join(", ")
        ));
    }
}
