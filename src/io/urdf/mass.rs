//! Masses and inertias of URDF links: the round-off repair of their inertia tensors
//! ([`INERTIA_ROUNDOFF`], [`BALL_RADIUS`]) and the load a joint holds up, which makes its
//! friction stiffness ([`friction_stiffness`]).

use super::error::{ErrorContext, UrdfError};
use super::options::UrdfOptions;
use super::validate::root_links;
use crate::dynamics::{from_quat, from_vec3};
use crate::dynamics::{to_quat, to_vec3};
use crate::law::stiffness::implicit_kappa;
use crate::law::Dof;
use crate::rapier::dynamics::{MassProperties, RigidBody, RigidBodyAdditionalMassProps};
use crate::rapier::geometry::Collider;
use crate::rapier::math::{Real, Rotation, Vector};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use rapier3d_urdf::urdf_rs;

/// Radius \[m\] of the solid ball whose inertia `0.4·m·r²` a link gets about the axes where
/// the URDF gives it none: every axis for a link without mass (given
/// [`UrdfOptions::min_link_mass`]), the zero principal axes for a link with mass.
pub const BALL_RADIUS: f64 = 0.05;

/// Relative round-off tolerance of inertia terms: a diagonal term or principal moment down
/// to `−INERTIA_ROUNDOFF × (the largest inertia term)` is round-off and read as 0.
pub const INERTIA_ROUNDOFF: f64 = 1e-9;

/// Absolute round-off tolerance of inertia terms \[kg·m²\], for links whose terms are all
/// tiny: far below any real part (a 1 g ball of 1 mm radius has 4e-10 kg·m²).
pub const INERTIA_ABS_ROUNDOFF: f64 = 1e-15;

/// Inertias: round-off below zero is read as zero, clearly negative diagonal terms are
/// refused, and the zero (or negative) principal moments of a dynamic link with mass get
/// the inertia of a ball ([`BALL_RADIUS`]); see the module docs.
pub(super) fn repair_inertias(
    context: &ErrorContext,
    robot: &mut urdf_rs::Robot,
    options: &UrdfOptions,
    notices: &mut Vec<String>,
) -> Result<(), UrdfError> {
    let roots: std::collections::HashSet<String> =
        root_links(robot).into_iter().map(String::from).collect();
    for link in robot.links.iter_mut() {
        let el = format!("link `{}`", link.name);
        let m = link.inertial.mass.value;
        let i = &mut link.inertial.inertia;
        let largest = [i.ixx, i.iyy, i.izz, i.ixy, i.ixz, i.iyz]
            .iter()
            .fold(0.0f64, |a, v| a.max(v.abs()));
        let tol = (INERTIA_ROUNDOFF * largest).max(INERTIA_ABS_ROUNDOFF);
        for (f, v) in [
            ("ixx", &mut i.ixx),
            ("iyy", &mut i.iyy),
            ("izz", &mut i.izz),
        ] {
            if *v < -tol {
                return Err(context.field(
                    &el,
                    format!("inertial.inertia.{f}"),
                    *v,
                    format!("a value >= 0 [kg·m²] (round-off down to -{tol:.1e} is read as 0)"),
                ));
            }
            if *v < 0.0 {
                notices.push(format!(
                    "{el}: inertial.inertia.{f} = {v:e} is round-off (within -{tol:.1e}): read \
                     as 0"
                ));
                *v = 0.0;
            }
        }
        let tensor = Matrix3::new(
            i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz,
        );
        let (p, axes) = principal_axes(&tensor);
        let mut sorted = [p[0], p[1], p[2]];
        sorted.sort_by(f64::total_cmp);
        // a tensor that is not positive semi-definite (real descriptions have them:
        // romeo, tiago): rapier reads its negative principal moments as 0, like a zero
        // inertia, so it gets the same treatment, with a notice that says so
        let not_psd = if p.min() < -tol {
            format!(
                "inertial.inertia is not positive semi-definite (principal moments [{:.3e}, \
                 {:.3e}, {:.3e}] kg·m²), ",
                sorted[0], sorted[1], sorted[2]
            )
        } else {
            String::new()
        };
        // a dynamic link with mass and a zero principal moment: rapier would lock its
        // rotation about that axis (infinite inertia); give it a ball's inertia there
        let fixed = options.fixed_base && roots.contains(&link.name);
        let zero: Vec<usize> = (0..3).filter(|&k| p[k] <= tol).collect();
        if m > 0.0 && !fixed && !zero.is_empty() {
            let ball = 0.4 * m * BALL_RADIUS * BALL_RADIUS;
            let mut t = tensor;
            for &k in &zero {
                let v = axes.matrix().column(k);
                t += (ball - p[k]) * v * v.transpose();
            }
            (i.ixx, i.iyy, i.izz) = (t[(0, 0)], t[(1, 1)], t[(2, 2)]);
            (i.ixy, i.ixz, i.iyz) = (t[(0, 1)], t[(0, 2)], t[(1, 2)]);
            notices.push(format!(
                "{el}: {not_psd}mass {m} kg with {} zero principal moment{} of inertia \
                 (inertial.inertia): given {ball:.3e} kg·m² there, the inertia of a ball of \
                 its mass and radius {BALL_RADIUS} m",
                zero.len(),
                if zero.len() > 1 { "s" } else { "" }
            ));
        } else if !not_psd.is_empty() {
            notices.push(format!("{el}: {not_psd}its negative moments are read as 0"));
        }
    }
    Ok(())
}

/// The principal moments and axes of the symmetric inertia tensor `tensor`, in double
/// precision: `tensor = R·diag(moments)·Rᵀ` with `R` a proper rotation (det +1), its columns
/// the principal axes. Equal moments (a wheel, a rod) and tiny ones (the small links of CAD
/// exports, 1e-6 kg·m²) come out right, which parry's f32 `with_inertia_matrix` does not
/// guarantee: it returns the x axis as the first principal axis when the smallest moment is
/// repeated or all the tensor's terms are below about 1e-5, whatever the tensor.
pub(crate) fn principal_axes(tensor: &Matrix3<f64>) -> (Vector3<f64>, Rotation3<f64>) {
    let eig = nalgebra::SymmetricEigen::new(*tensor);
    let mut axes = eig.eigenvectors;
    if axes.determinant() < 0.0 {
        // a reflection: the opposite of an axis is an axis too
        axes.column_mut(2).neg_mut();
    }
    (eig.eigenvalues, Rotation3::from_matrix_unchecked(axes))
}

/// Rapier mass properties of mass `mass` \[kg\] at `com` (body frame) with the inertia
/// tensor `tensor` \[kg·m²\] about it (body axes), diagonalised in double precision
/// ([`principal_axes`]); negative moments (round-off) are read as 0, as rapier reads them.
pub(crate) fn mass_properties(
    com: &Vector3<f64>,
    mass: f64,
    tensor: &Matrix3<f64>,
) -> MassProperties {
    let (moments, axes) = principal_axes(tensor);
    principal_mass_properties(com, mass, &moments, &axes)
}

/// Rapier mass properties of mass `mass` \[kg\] at `com` (body frame) with the principal
/// moments `moments` \[kg·m²\] about the principal axes `axes` (body frame; negative
/// moments read as 0).
pub(crate) fn principal_mass_properties(
    com: &Vector3<f64>,
    mass: f64,
    moments: &Vector3<f64>,
    axes: &Rotation3<f64>,
) -> MassProperties {
    let frame = UnitQuaternion::from_rotation_matrix(axes);
    MassProperties::with_principal_inertia_frame(
        to_vec3(com),
        mass as Real,
        to_vec3(&moments.map(|m| m.max(0.0))),
        to_quat(&frame),
    )
}

/// The mass properties of a URDF inertial in its link's frame: its tensor turned by the
/// inertial's `rpy` (rapier3d-urdf drops it), diagonalised in double precision.
pub(super) fn inertial_mass_properties(inertial: &urdf_rs::Inertial) -> MassProperties {
    let i = &inertial.inertia;
    let tensor = Matrix3::new(
        i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz,
    );
    let rpy = inertial.origin.rpy.0;
    let rot = Rotation3::from_euler_angles(rpy[0], rpy[1], rpy[2]);
    let com = Vector3::from(inertial.origin.xyz.0);
    mass_properties(
        &com,
        inertial.mass.value,
        &(rot.matrix() * tensor * rot.matrix().transpose()),
    )
}

/// Gives a link's body `body` the mass properties `mp`, so that rapier keeps them. Rapier
/// recomputes a body's mass properties (at its first step) as the sum of its colliders' (each
/// moved to its pose on the body) and its own (`additional`), with parry's `+`, which
/// diagonalises the sum in f32 (the routine [`principal_axes`] replaces) as soon as two
/// terms are not zero, and a massless collider away from the body's origin is not zero (its
/// centre and frame moved). So: a massless collider off the origin without rotation gets
/// massless properties at the pre-image of the origin (they move to exactly zero); when one
/// collider (rotated) is left not zero, it carries `mp` (in its own frame) and the body none;
/// otherwise the body carries `mp`. Returns the relative error of the inertia tensor rapier
/// will compute where that is not `mp`'s (two rotated colliders or more): the caller says so.
pub(crate) fn place_mass(
    body: &mut RigidBody,
    colliders: &mut [Collider],
    mp: MassProperties,
) -> Option<f64> {
    let zero = MassProperties::default();
    let pose = |c: &Collider| c.position_wrt_parent().copied().unwrap_or(*c.position());
    let mut not_zero = Vec::new();
    for (k, c) in colliders.iter_mut().enumerate() {
        let p = pose(c);
        if c.mass_properties().transform_by(&p) == zero {
            continue;
        }
        let undo = MassProperties::with_principal_inertia_frame(
            -p.translation,
            0.0,
            Vector::ZERO,
            Rotation::IDENTITY,
        );
        if c.mass() == 0.0 && undo.transform_by(&p) == zero {
            c.set_mass_properties(undo);
        } else {
            not_zero.push(k);
        }
    }
    match not_zero.as_slice() {
        [k] if colliders[*k].mass() == 0.0 => {
            let c = &mut colliders[*k];
            let p = pose(c);
            c.set_mass_properties(mp.transform_by(&p.inverse()));
            body.set_additional_mass_properties(zero, false);
        }
        _ => body.set_additional_mass_properties(mp, false),
    }
    // the sum as rapier makes it (`RigidBodyMassProps::recompute_mass_properties_from_colliders`)
    let mut sum = zero;
    for c in colliders.iter() {
        sum += c.mass_properties().transform_by(&pose(c));
    }
    let own = body.mass_properties().additional_local_mprops.as_deref();
    if let Some(RigidBodyAdditionalMassProps::MassProps(m)) = own {
        sum += *m;
    }
    let tensor = |m: &MassProperties| {
        let i = m.reconstruct_inertia_matrix();
        Matrix3::from_fn(|r, k| i.col(k)[r] as f64)
    };
    let (want, got) = (tensor(&mp), tensor(&sum));
    let scale = want.abs().max().max(f64::MIN_POSITIVE);
    let err = (got - want).abs().max() / scale;
    (err > 1e-4).then_some(err)
}

/// Friction spring stiffness rule `Kf = κ_eff·m_eff/h²` [N/m or N·m/rad] (module docs):
/// the implicit rule of the blocked DOFs ([`crate::law::stiffness::implicit_kappa`]) for a
/// load of mass or moment of inertia `m_eff` (the links the joint holds up, about its axis)
/// at pose scale `pose_scale` \[m\] (the anchor's distance from the origin plus the load's
/// radius of gyration), substep `h` \[s\].
pub fn friction_stiffness(m_eff: f64, pose_scale: f64, substep: f64) -> f64 {
    implicit_kappa(substep, pose_scale) * m_eff / (substep * substep)
}

/// Mass, world centre of mass and world inertia tensor (about that centre) of a link.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LinkMass {
    pub(crate) m: f64,
    pub(crate) c: Vector3<f64>,
    pub(crate) inertia: Matrix3<f64>,
}

impl LinkMass {
    /// No mass.
    pub(crate) const ZERO: LinkMass = LinkMass {
        m: 0.0,
        c: Vector3::new(0.0, 0.0, 0.0),
        inertia: Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
    };

    /// The sum of two masses, the inertia about their common centre (parallel axis
    /// theorem); no mass at all gives [`Self::ZERO`].
    pub(crate) fn add(self, o: LinkMass) -> LinkMass {
        let m = self.m + o.m;
        if m <= 0.0 {
            return LinkMass::ZERO;
        }
        let c = (self.c * self.m + o.c * o.m) / m;
        let shift = |x: &LinkMass| {
            let d = x.c - c;
            x.inertia + x.m * (Matrix3::identity() * d.norm_squared() - d * d.transpose())
        };
        LinkMass {
            m,
            c,
            inertia: shift(&self) + shift(&o),
        }
    }

    /// From the URDF inertial at the link's world pose; a link without mass counts
    /// `min_mass` with the inertia of a 5 cm ball (as its body gets).
    pub(super) fn of(
        inertial: &urdf_rs::Inertial,
        pose: &crate::rapier::math::Pose,
        min_mass: f64,
    ) -> Self {
        let i = &inertial.inertia;
        let (mut m, mut ic) = (
            inertial.mass.value,
            Matrix3::new(
                i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz,
            ),
        );
        if m <= 0.0 {
            m = min_mass;
            ic = Matrix3::identity() * (0.4 * m * 0.05 * 0.05);
        }
        let rpy = inertial.origin.rpy.0;
        let rot = from_quat(pose.rotation).to_rotation_matrix()
            * Rotation3::from_euler_angles(rpy[0], rpy[1], rpy[2]);
        let c = from_vec3(pose.translation)
            + from_quat(pose.rotation) * Vector3::from(inertial.origin.xyz.0);
        LinkMass {
            m,
            c,
            inertia: rot.matrix() * ic * rot.matrix().transpose(),
        }
    }
}

/// The load a joint's free DOF `dof` holds up: the link `first` and every link beyond it
/// (`children`), as a mass \[kg\] (translation) or a moment of inertia about `axis` through
/// `anchor` [kg·m²] (rotation), and the pose scale `|anchor| + √(I/m)` \[m\] of the
/// implicit rule (world coordinates).
pub(crate) fn load_beyond(
    links: &[LinkMass],
    children: &[Vec<usize>],
    first: usize,
    dof: Dof,
    anchor: &Vector3<f64>,
    axis: &Vector3<f64>,
) -> (f64, f64) {
    let a = axis.normalize();
    let (mut m, mut i_axis, mut i_mean) = (0.0, 0.0, 0.0);
    let mut seen = vec![false; links.len()];
    let mut stack = vec![first];
    while let Some(l) = stack.pop() {
        if std::mem::replace(&mut seen[l], true) {
            continue;
        }
        let lm = &links[l];
        let d = lm.c - anchor;
        m += lm.m;
        i_axis += (a.transpose() * lm.inertia * a)[0] + lm.m * d.cross(&a).norm_squared();
        i_mean += lm.inertia.trace() / 3.0 + 2.0 / 3.0 * lm.m * d.norm_squared();
        stack.extend(children[l].iter().copied());
    }
    let gyration = if m > 0.0 { (i_mean / m).sqrt() } else { 0.0 };
    let scale = anchor.norm() + gyration;
    if dof.is_rotation() {
        (i_axis.max(0.0), scale)
    } else {
        (m, scale)
    }
}
