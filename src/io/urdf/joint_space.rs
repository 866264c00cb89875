//! The joint-space inertia of a robot's tree at one pose, as MuJoCo's compiler measures it
//! for a joint's `springdamper` (its `dof_invweight0`): the diagonal of `M⁻¹`, where `M`
//! is the joint-space inertia matrix of every degree of freedom of the tree (a floating
//! base's six with them).
//!
//! # The matrix (composite rigid bodies)
//! A degree of freedom `i` moves the link `l_i` and every link beyond it (`T_i`, its
//! subtree) with the unit twist `S_i = (ω, v₀)`: the angular velocity and the velocity of
//! the point at the world origin (a hinge of axis `a` through `p`: `(a, p × a)`; a slide
//! along `a`: `(0, a)`). A link of mass `m`, centre `c` and inertia `I_c` about it (world
//! axes) has the spatial inertia at the origin
//!
//! ```text
//! I_o = [ I_c + m·[c]ₓᵀ[c]ₓ   m·[c]ₓ ]      (½·(ω, v₀)ᵀ·I_o·(ω, v₀) = ½·ωᵀI_cω + ½·m·|v₀ + ω × c|²)
//!       [ m·[c]ₓᵀ            m·1    ]
//! ```
//!
//! and the kinetic energy of the tree is `½·q̇ᵀ·M·q̇` with
//! `M_ij = S_iᵀ·(Σ_{k ∈ T_i ∩ T_j} I_o,k)·S_j`: the composite inertia of the deeper of the
//! two subtrees where one holds the other, 0 where they are apart (Featherstone's
//! composite-rigid-body algorithm, summed directly). A rotor's armature adds to `M_ii`.

use super::mass::LinkMass;
use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3, Vector6};

/// A degree of freedom of a tree ([`inverse_inertia_diagonal`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TreeDof {
    /// The link it moves (with every link beyond it, by the tree's `children`).
    pub link: usize,
    /// Its unit motion `(ω, v₀)`: angular velocity \[rad/s\] and the velocity of the point
    /// at the world origin \[m/s\], world axes (module docs).
    pub twist: Vector6<f64>,
    /// Inertia added to its own diagonal term (a rotor's armature) [kg·m² or kg].
    pub armature: f64,
}

impl TreeDof {
    /// A rotation about the unit `axis` through `anchor` (world).
    pub(crate) fn hinge(link: usize, anchor: &Vector3<f64>, axis: &Vector3<f64>) -> Self {
        let v = anchor.cross(axis);
        TreeDof {
            link,
            twist: Vector6::new(axis.x, axis.y, axis.z, v.x, v.y, v.z),
            armature: 0.0,
        }
    }

    /// A translation along the unit `axis` (world).
    pub(crate) fn slide(link: usize, axis: &Vector3<f64>) -> Self {
        TreeDof {
            link,
            twist: Vector6::new(0.0, 0.0, 0.0, axis.x, axis.y, axis.z),
            armature: 0.0,
        }
    }

    /// The six motions of a free (floating) `link`: rotations about the world axes through
    /// the origin, then translations along them.
    pub(crate) fn free(link: usize) -> [Self; 6] {
        std::array::from_fn(|k| {
            let mut twist = Vector6::zeros();
            twist[k] = 1.0;
            TreeDof {
                link,
                twist,
                armature: 0.0,
            }
        })
    }
}

/// The spatial inertia of `l` at the world origin (module docs).
fn spatial_inertia(l: &LinkMass) -> Matrix6<f64> {
    let cx = l.c.cross_matrix();
    let mut s = Matrix6::zeros();
    s.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(l.inertia + l.m * cx.transpose() * cx));
    s.fixed_view_mut::<3, 3>(0, 3).copy_from(&(l.m * cx));
    s.fixed_view_mut::<3, 3>(3, 0)
        .copy_from(&(l.m * cx.transpose()));
    s.fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&(Matrix3::identity() * l.m));
    s
}

/// Which links are `first` or beyond it (`children`; a link reached twice counts once).
fn subtree(children: &[Vec<usize>], first: usize) -> Vec<bool> {
    let mut inside = vec![false; children.len()];
    let mut stack = vec![first];
    while let Some(l) = stack.pop() {
        if l >= inside.len() || std::mem::replace(&mut inside[l], true) {
            continue;
        }
        stack.extend(children[l].iter().copied());
    }
    inside
}

/// The diagonal of `M⁻¹` of the degrees of freedom `dofs` of the tree of `links`
/// (`children[l]`: the links jointed beyond `l`), in their order (module docs): what a unit
/// impulse along one of them changes its rate by, the others free. `None` where `M` is not
/// positive definite (a degree of freedom that moves no mass), or not finite.
pub(crate) fn inverse_inertia_diagonal(
    links: &[LinkMass],
    children: &[Vec<usize>],
    dofs: &[TreeDof],
) -> Option<Vec<f64>> {
    let n = dofs.len();
    // per degree of freedom: its subtree and the composite inertia of it
    let trees: Vec<Vec<bool>> = dofs.iter().map(|d| subtree(children, d.link)).collect();
    let composite: Vec<Matrix6<f64>> = trees
        .iter()
        .map(|inside| {
            (links.iter().zip(inside))
                .filter(|(_, &i)| i)
                .map(|(l, _)| spatial_inertia(l))
                .sum()
        })
        .collect();
    let m = DMatrix::from_fn(n, n, |i, j| {
        let (di, dj) = (&dofs[i], &dofs[j]);
        let deeper = if trees[i].get(dj.link) == Some(&true) {
            Some(j)
        } else if trees[j].get(di.link) == Some(&true) {
            Some(i)
        } else {
            None
        };
        let shared = deeper.map_or(0.0, |k| (di.twist.transpose() * composite[k] * dj.twist)[0]);
        shared + if i == j { di.armature } else { 0.0 }
    });
    if !m.iter().all(|x| x.is_finite()) {
        return None;
    }
    let inverse = m.cholesky()?.inverse();
    let diagonal: Vec<f64> = (0..n).map(|i| inverse[(i, i)]).collect();
    diagonal
        .iter()
        .all(|x| x.is_finite() && *x > 0.0)
        .then_some(diagonal)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ball(m: f64, c: Vector3<f64>, i: f64) -> LinkMass {
        LinkMass {
            m,
            c,
            inertia: Matrix3::identity() * i,
        }
    }

    /// A slide on a 1 kg body alone: `M = m`, `1/(M⁻¹)` the mass; a hinge through its
    /// centre: its inertia about the axis; through a point at `r`: `I + m·r²`.
    #[test]
    fn one_body_s_inertia_is_its_mass_or_its_moment_about_the_axis() {
        let links = [ball(2.0, Vector3::new(0.3, 0.0, 0.0), 0.05)];
        let children = [vec![]];
        let z = Vector3::z();
        let d = inverse_inertia_diagonal(&links, &children, &[TreeDof::slide(0, &z)]).unwrap();
        assert!((1.0 / d[0] - 2.0).abs() < 1e-12, "{d:?}");
        let pivot = Vector3::new(0.1, 0.0, 0.0);
        let d =
            inverse_inertia_diagonal(&links, &children, &[TreeDof::hinge(0, &pivot, &z)]).unwrap();
        let expected = 0.05 + 2.0 * 0.2 * 0.2;
        assert!(
            (1.0 / d[0] - expected).abs() < 1e-12,
            "{} {expected}",
            1.0 / d[0]
        );
    }

    /// A hinge (axis z through the origin) between a free base (mass `m1`, inertia `I1`
    /// about z, centred at the origin) and a point-like link `m2` at `r` along x: the
    /// hinge's effective inertia with the base free, by hand from the planar Lagrangian
    /// (`x, y, θ₁, φ`; the link at `(x + r·cos(θ₁+φ), y + r·sin(θ₁+φ))`),
    /// `1/(M⁻¹)_φφ = m2·r²·m1·I1 / ((m1 + m2)·I1 + m1·m2·r²)`: below the link's `m2·r²`
    /// about a fixed base, tending to it as the base grows heavy.
    #[test]
    fn a_hinge_on_a_free_base_has_the_inertia_of_the_planar_lagrangian() {
        let (m1, i1, m2, r, i2) = (3.0, 0.4, 1.5, 0.6, 1e-9);
        let links = [
            ball(m1, Vector3::zeros(), i1),
            ball(m2, Vector3::new(r, 0.0, 0.0), i2),
        ];
        let children = [vec![1], vec![]];
        let mut dofs = TreeDof::free(0).to_vec();
        dofs.push(TreeDof::hinge(1, &Vector3::zeros(), &Vector3::z()));
        let d = inverse_inertia_diagonal(&links, &children, &dofs).unwrap();
        let expected = m2 * r * r * m1 * i1 / ((m1 + m2) * i1 + m1 * m2 * r * r);
        let got = 1.0 / d[6];
        // (the link's own 1e-9 kg·m² about its centre adds to m2·r²)
        assert!((got - expected).abs() < 1e-8, "{got} {expected}");
        assert!(got < m2 * r * r);
        // the base a thousand times heavier: nearly the link's inertia about a fixed axis
        let links = [
            ball(1e3 * m1, Vector3::zeros(), 1e3 * i1),
            ball(m2, Vector3::new(r, 0.0, 0.0), i2),
        ];
        let d = inverse_inertia_diagonal(&links, &children, &dofs).unwrap();
        assert!((1.0 / d[6] - m2 * r * r).abs() < 2e-3 * m2 * r * r);
    }

    /// A rotor's armature adds to its own degree of freedom; a degree of freedom that
    /// moves nothing makes `M` singular: `None`.
    #[test]
    fn armature_adds_and_a_massless_degree_of_freedom_is_none() {
        let links = [ball(2.0, Vector3::zeros(), 0.05), LinkMass::ZERO];
        let children = [vec![], vec![]];
        let mut hinge = TreeDof::hinge(0, &Vector3::zeros(), &Vector3::x());
        hinge.armature = 0.01;
        let d = inverse_inertia_diagonal(&links, &children, &[hinge]).unwrap();
        assert!((1.0 / d[0] - 0.06).abs() < 1e-12, "{d:?}");
        let nothing = TreeDof::slide(1, &Vector3::x());
        assert_eq!(
            inverse_inertia_diagonal(&links, &children, &[nothing]),
            None
        );
    }
}
