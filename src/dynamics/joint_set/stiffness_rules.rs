//! The blocked stiffness of the set's joints resolved from the substep (docs/kjoint2.md
//! §5: the implicit rule or the Radioss rule, shared per body), the stable time steps of
//! Radioss' explicit scheme, and the loads each joint holds up: the part of the joint set
//! that reads the bodies' masses.

use super::KjointHandle;
use super::KjointSet;
use crate::dynamics::convert::from_vec3;
use crate::dynamics::joint::{massless, Kjoint};
use crate::dynamics::substep::mean_inertia;
use crate::error::SimError;
use crate::law;
use crate::law::stiffness::{self, BodyMass};
use crate::rapier::dynamics::{RigidBody, RigidBodyHandle, RigidBodySet};
use nalgebra::Vector3;
use std::collections::HashMap;

impl KjointSet {
    /// Stable time steps of Radioss' explicit scheme for a joint (docs/kjoint2.md §5),
    /// translational and rotational ([`stiffness::StableDt`]), for the stiffness resolved so far
    /// (`None` before the first step). `K` is the largest tangent stiffness of a DOF: `Kn`/`KR` on
    /// a blocked DOF; on a free one its spring (a curve's largest slope times its scale), plus
    /// its friction spring (which is also its stop) or else its stop stiffness, or the lock
    /// stiffness when the joint has a sensor and that is larger (the lock holds the law's
    /// force and acts alone, docs/kjoint2.md §4.5); a connector law's largest stiffness
    /// counts too. `L` is the initial joint length `L0`.
    pub fn stable_dt(&self, h: KjointHandle, bodies: &RigidBodySet) -> Option<stiffness::StableDt> {
        let j = self.get(h)?;
        let k = j.blocked?;
        let masses = [
            // (the offsets do not enter the stable steps)
            body_mass(bodies.get(j.body1)?, &j.frames.local_anchor1, true),
            body_mass(bodies.get(j.body2)?, &j.frames.local_anchor2, true),
        ];
        let free = j.property.joint_type.free_dofs();
        let lock = j.property.sensor.is_some();
        let (mut kt, mut kr) = (0.0_f64, 0.0_f64);
        for d in crate::law::Dof::ALL {
            let kb = k.of(d);
            let kd = if free[d.index()] {
                let law = j.property.dof(d);
                let spring = law.stiffness_scale().abs()
                    * law
                        .stiffness_curve
                        .as_ref()
                        .map_or(1.0, |c| c.max_abs_slope());
                // with friction active the friction spring is also the stop (§4.2); else the
                // stop stiffness is Kf when set
                let stop =
                    if law.friction_active() || (law.has_stops() && law.friction_stiffness > 0.0) {
                        law.friction_stiffness
                    } else if law.has_stops() {
                        kb
                    } else {
                        0.0
                    };
                // a sensor lock holds the law's force and replaces its stiffness by the
                // lock's (docs/kjoint2.md §4.5): the larger of the two phases
                (spring + stop).max(if lock { kb } else { 0.0 })
            } else {
                kb
            };
            if d.is_rotation() {
                kr = kr.max(kd);
            } else {
                kt = kt.max(kd);
            }
        }
        let (ct, cr) = j.connector.max_stiffness(&k);
        Some(stiffness::stable_dt(
            masses,
            kt.max(ct),
            kr.max(cr),
            j.property.resolved_critical_damping(),
            j.initial_length,
        ))
    }

    /// Resolves the blocked stiffness of every joint for substep `h` (docs/kjoint2.md §5): user
    /// `Kn` directly; `Kn = 0` by the property's rule ([`crate::law::AutomaticStiffness`]): the
    /// implicit rule from each joint's load side ([`Self::joint_loads`],
    /// [`stiffness::implicit_blocked_stiffness`]), or the Radioss rule (also for a joint with
    /// a planar friction law, whose normal load is read from the law's blocked forces: on a
    /// DOF the substep does not resolve, `K·q` lags the transmitted force), where automatic
    /// joints share each body's budget `2m/(α·h²)` equally after the user-stiffness joints
    /// on that body have taken theirs. Every joint also gets the Radioss automatic value for
    /// the substep as the automatic stick stiffness of a planar friction law
    /// (docs/planar_friction.md §4: chosen from the substep like the automatic penalty of
    /// docs/kjoint2.md §5): its shared Radioss stiffness when `Kn = 0` (whatever the rule of its
    /// blocked DOFs), else the Radioss penalty it would get alone with `ScF = 1`.
    ///
    /// Only the joints of the islands that changed are resolved again: an island (joints
    /// linked through dynamic bodies) holding a joint whose stiffness is unresolved (`blocked`
    /// is `None`: inserted, its property changed, a joint on its bodies removed, a mass of its
    /// bodies changed). The others keep the stiffness they had: the implicit rule reads the
    /// bodies' poses, and resolving a running island again at its current pose changed its
    /// motion (a chain swinging on its own parted by 3.6 mm within 2 s from the same chain
    /// when a pendulum was inserted 20 m away; a user trial of one world of many robots,
    /// 2026-12-04).
    pub(in crate::dynamics) fn resolve_stiffness(
        &mut self,
        bodies: &RigidBodySet,
        h: f64,
    ) -> Result<(), SimError> {
        // every jointed body first: the load of a joint sums the masses beyond it
        for j in &self.joints {
            for (which, hb) in [(1, j.body1), (2, j.body2)] {
                if let Some(b) = bodies.get(hb) {
                    check_body_mass(j, which, b)?;
                }
            }
        }
        // the frame the substep divides (for the advice of a joint the noise bound softens)
        let frame = h * self.settings().substeps as f64;
        let mut n_auto: HashMap<RigidBodyHandle, usize> = HashMap::new();
        let mut k_user: HashMap<RigidBodyHandle, f64> = HashMap::new();
        for j in &self.joints {
            for hb in [j.body1, j.body2] {
                if j.property.automatic_stiffness() {
                    *n_auto.entry(hb).or_default() += 1;
                } else {
                    *k_user.entry(hb).or_default() += j.property.kn;
                }
            }
        }
        // a planar or joint friction law reads the law's blocked forces (its normal load): they must
        // be the forces the joint transmits, so its blocked DOFs stay resolved (Radioss rule)
        let implicit = |j: &Kjoint| {
            j.property.automatic_stiffness()
                && j.property.automatic == law::AutomaticStiffness::Implicit
                && !j.connector_law().reads_reactions()
        };
        let graph = LoadGraph::new(&self.joints, bodies);
        let loads = if self.joints.iter().any(implicit) {
            self.joint_loads_of(&graph, bodies)
        } else {
            Vec::new()
        };
        let stale = graph.stale_joints(&self.joints);
        for (ji, j) in self.joints.iter_mut().enumerate() {
            if !stale[ji] || bodies.get(j.body1).is_none() || bodies.get(j.body2).is_none() {
                continue;
            }
            let (b1, b2) = (&bodies[j.body1], &bodies[j.body2]);
            if !b1.is_dynamic() && !b2.is_dynamic() {
                // nothing to scale with, and nothing to move: the joint is inert (out of the
                // stages, `Off::Inert`) until a body is dynamic again, and resolved then
                continue;
            }
            if j.property.automatic_stiffness() && (massless(b1) || massless(b2)) {
                // nothing to scale with: out of the stages from the next analysis, which
                // a body that lost its mass since the last one calls for
                // (`Off::Massless`), until it has one again; its stiffness kept meanwhile
                self.massless_found |= j.disabled.is_none();
                continue;
            }
            // a fixed body's anchor offset counts in the Radioss rule's r² where the property
            // asks for Radioss' rule (a deck's, docs/kjoint2.md §5), not where the rule is
            // used for a connector's sake: a fixed body does not turn, and the centre of a
            // ground (rapier's world body, at the origin) is where the user put it; a block
            // sliding on a planar friction plate 10 m from the ground's origin got 360 N/m
            // (1/r²) where at the origin 3.6e6 N/m, bounced, and slid 38 % too far (an
            // offshore engineer's trial, 2026-12-04)
            let offsets = j.property.automatic == law::AutomaticStiffness::Radioss;
            let masses = [
                body_mass(&bodies[j.body1], &j.frames.local_anchor1, offsets),
                body_mass(&bodies[j.body2], &j.frames.local_anchor2, offsets),
            ];
            let share = [j.body1, j.body2].map(|hb| {
                let b = &bodies[hb];
                let budget = 2.0 * b.mass() as f64 / (stiffness::ALPHA * h * h);
                let user = k_user.get(&hb).copied().unwrap_or(0.0);
                // what the user joints leave, at least a tenth of the budget
                let left = ((budget - user) / budget).clamp(0.1, 1.0);
                left / n_auto.get(&hb).copied().unwrap_or(1).max(1) as f64
            });
            // (set again below for a joint of the implicit rule)
            j.noise_bound = None;
            if !j.property.automatic_stiffness() {
                j.blocked = Some(stiffness::user_blocked_stiffness(
                    &j.property,
                    j.initial_length,
                ));
                // the automatic penalty this joint would get alone, with ScF = 1 (its own ScF
                // scales KR here, and its Kn must not eat the body's budget)
                let auto = crate::law::KjointProperty::new(j.property.joint_type);
                j.connector
                    .set_automatic_stiffness(stiffness::automatic_blocked_stiffness(
                        &auto,
                        masses,
                        j.initial_length,
                        h,
                        [1.0, 1.0],
                    ));
                continue;
            }
            let load = loads.get(ji).copied().flatten().filter(|_| implicit(j));
            let rule = |p: &law::KjointProperty| {
                let radioss =
                    stiffness::automatic_blocked_stiffness(p, masses, j.initial_length, h, share);
                let k = match &load {
                    Some(load) => stiffness::implicit_blocked_stiffness(p, load, h),
                    None => radioss,
                };
                (radioss, k)
            };
            let (radioss, k) = rule(&j.property);
            let finite =
                |k: &law::BlockedStiffness| k.translational.is_finite() && k.rotational.is_finite();
            if !finite(&k) {
                // ScF is to blame only when the stiffness without it is finite; else the
                // substep is too small for the bodies (the stiffness grows as m/h²)
                let unscaled = law::KjointProperty {
                    scale_factor: 0.0,
                    ..(*j.property).clone()
                };
                if finite(&rule(&unscaled).1) {
                    return Err(SimError::Property {
                        joint: j.name.clone(),
                        source: crate::error::PropertyError::field(
                            "scale_factor (ScF)",
                            j.property.scale_factor,
                            "a factor whose automatic stiffnesses ScF·KX, ScF·KR are finite",
                        ),
                    });
                }
                return Err(SimError::InvalidJoint {
                    joint: j.name.clone(),
                    reason: format!(
                        "the automatic blocked stiffness is not finite at the substep h = {h:e} s \
                         (it grows as m/h²): use a larger substep, or set Kn"
                    ),
                });
            }
            if !(k.translational > 0.0)
                && !j.property.joint_type.free_dofs()[..3].iter().all(|f| *f)
            {
                // (a joint with no dynamic body, or with a dynamic body without mass, is
                // skipped above): a load side without mass leaves the rule nothing to scale
                // with
                return Err(SimError::InvalidJoint {
                    joint: j.name.clone(),
                    reason: "automatic stiffness is zero: a body has no mass (give it a \
                             collider or mass, or set Kn)"
                        .into(),
                });
            }
            j.blocked = Some(k);
            j.noise_bound = load.and_then(|load| stiffness::NoiseBound::of(&load, h, frame));
            j.connector.set_automatic_stiffness(radioss);
        }
        self.auto_dt = Some(h);
        self.resolved_masses.clear();
        for j in &self.joints {
            for hb in [j.body1, j.body2] {
                if let Some(b) = bodies.get(hb).filter(|b| b.is_dynamic()) {
                    self.resolved_masses
                        .insert(hb, b.mass_properties().local_mprops);
                }
            }
        }
        Ok(())
    }

    /// Resolves the blocked stiffness again at this substep where a jointed body's mass
    /// properties are no longer those it was resolved from (`Self::resolved_masses`, the
    /// dynamic bodies' at the resolution): the user set a mass
    /// (`RigidBody::set_additional_mass`, `Collider::set_mass`), added or removed a collider,
    /// changed a density, or switched the body between dynamic and fixed or kinematic (a
    /// gripper made fixed carries the load hung on it: the side of the joint that carries
    /// the load is another). Every rule depends on them (the implicit rule's `κ_eff·m_L/h²`
    /// on the masses beyond the joint, the Radioss rule's `2m/(α·h²)` on its bodies'), and a
    /// stiffness left at the old masses lets a joint whose load grew a hundredfold sag a
    /// hundred times as far. Where a part of the set had no collider at the analysis, its
    /// structure is analysed again at the next substep too (a body given one can be touched
    /// by rapier's contacts, `substep::ContactPrediction`). A mass that changes at every
    /// substep costs a resolution (O(joints)) at each. Called by stage 3 after the gather
    /// stage derived a body's mass properties again, which it does after each analysis
    /// (a body switched between dynamic and fixed is one) and when they change: a
    /// comparison per jointed body then, not every substep. Checked whether or not other
    /// joints wait for their resolution: only their islands are resolved
    /// ([`Self::resolve_stiffness`]).
    pub(in crate::dynamics) fn check_masses(&mut self, bodies: &RigidBodySet) {
        // the bodies resolved as dynamic that are no longer, or whose mass changed
        let mut changed: std::collections::HashSet<RigidBodyHandle> = self
            .resolved_masses
            .iter()
            .filter(|(hb, mp)| {
                bodies
                    .get(**hb)
                    .is_some_and(|b| !b.is_dynamic() || b.mass_properties().local_mprops != **mp)
            })
            .map(|(hb, _)| *hb)
            .collect();
        // and those dynamic now that were not (a joint inserted since is unresolved anyway)
        changed.extend(
            self.joints
                .iter()
                .filter(|j| j.blocked.is_some())
                .flat_map(|j| [j.body1, j.body2])
                .filter(|hb| {
                    !self.resolved_masses.contains_key(hb)
                        && bodies.get(*hb).is_some_and(|b| b.is_dynamic())
                }),
        );
        // (out of the record: a body of a joint removed since stays in it until the next
        // resolution, and one found changed at every analysis analysed the set again at
        // every substep, dropping the energy book's pending end-rate correction each time;
        // a review, 2026-12-04. A joint's body is recorded again when it is resolved.)
        self.resolved_masses.retain(|hb, _| !changed.contains(hb));
        if !self
            .joints
            .iter()
            .any(|j| changed.contains(&j.body1) || changed.contains(&j.body2))
        {
            return;
        }
        // the joints on those bodies, and with them their islands ([`Self::resolve_stiffness`])
        for j in &mut self.joints {
            if changed.contains(&j.body1) || changed.contains(&j.body2) {
                j.blocked = None;
            }
        }
        self.auto_dt = None;
        // (a part of the set without a collider at the analysis may have one now; where
        // one had, rapier's contacts are predicted for all its bodies already)
        if !std::iter::once(&self.data)
            .chain(&self.tiles)
            .all(|d| d.colliders)
        {
            self.data.valid = false;
        }
    }

    /// Marks unresolved the automatic stiffness of the joints on a dynamic body of a joint
    /// removed since the last substep ([`Self::removed_bodies`]): their island changed. A
    /// fixed or kinematic body (the ground every robot of a world stands on) links no
    /// islands: the joints of other islands on it keep their stiffness (a robot's base joint
    /// removed from a shared ground resolved every other robot's joints to the ground again
    /// at their current poses; a review, 2026-12-04).
    pub(in crate::dynamics) fn unresolve_beside_removed(&mut self, bodies: &RigidBodySet) {
        let gone: std::collections::HashSet<RigidBodyHandle> =
            std::mem::take(&mut self.removed_bodies)
                .into_iter()
                .filter(|hb| bodies.get(*hb).is_some_and(|b| b.is_dynamic()))
                .collect();
        for k in &mut self.joints {
            if k.property.automatic_stiffness()
                && (gone.contains(&k.body1) || gone.contains(&k.body2))
            {
                k.blocked = None;
            }
        }
    }

    /// The load side of every joint for the implicit stiffness rule
    /// ([`stiffness::JointLoad`], `None` for a joint whose body left the world), from the
    /// graph of the joints: bodies are nodes (every fixed or kinematic body is one node, the
    /// ground), joints are edges. A joint whose removal splits its part of the graph (a
    /// bridge, found by a depth-first search with low links) carries the side without the
    /// ground, or the lighter side when neither holds the ground; a joint in a loop carries
    /// the whole island (the bodies linked to it through dynamic bodies). O(bodies + joints).
    pub fn joint_loads(
        &self,
        bodies: &RigidBodySet,
    ) -> std::collections::BTreeMap<KjointHandle, Option<stiffness::JointLoad>> {
        let loads = self.joint_loads_by_slot(bodies);
        self.joints.iter().map(|j| j.handle).zip(loads).collect()
    }

    /// [`Self::joint_loads`] in the order of the set's joints (their slots): the graph of
    /// bodies and joints ([`LoadGraph`]), its islands and bridges, then each joint's side.
    fn joint_loads_by_slot(&self, bodies: &RigidBodySet) -> Vec<Option<stiffness::JointLoad>> {
        self.joint_loads_of(&LoadGraph::new(&self.joints, bodies), bodies)
    }

    /// [`Self::joint_loads_by_slot`] of the set's graph `graph`.
    fn joint_loads_of(
        &self,
        graph: &LoadGraph,
        bodies: &RigidBodySet,
    ) -> Vec<Option<stiffness::JointLoad>> {
        let island_sums = graph.island_sums();
        let dfs = graph.bridges();
        self.joints
            .iter()
            .zip(&graph.edges)
            .enumerate()
            .map(|(e, (j, ab))| {
                let (a, b) = (*ab)?;
                let p1 = crate::dynamics::joint::body_pose(bodies, j.body1)?;
                let anchor = p1.point(&j.frames.local_anchor1);
                let c = dfs.child[e];
                let parent = if c == a { b } else { a };
                let bridge = c != NONE && dfs.low[c] > dfs.disc[parent];
                let side = if bridge {
                    // the lighter side of a bridge (the one not holding the ground)
                    let r = dfs.root_of[c];
                    let near = dfs.sub[r].minus(&dfs.sub[c]);
                    if r == 0 || dfs.sub[c].m <= near.m {
                        dfs.sub[c]
                    } else {
                        near
                    }
                } else {
                    let v = if a != 0 { a } else { b };
                    island_sums[v]
                };
                Some(side.load(&anchor))
            })
            .collect()
    }
}

/// Additive mass sums of a set of bodies: `Σm`, `Σm·c`, `Σm·|c|²`, `Σ I_mean`.
#[derive(Clone, Copy, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
struct Sums {
    m: f64,
    mc: Vector3<f64>,
    mcc: f64,
    i: f64,
}

impl Sums {
    fn add(&mut self, o: &Sums) {
        self.m += o.m;
        self.mc += o.mc;
        self.mcc += o.mcc;
        self.i += o.i;
    }

    fn minus(&self, o: &Sums) -> Sums {
        Sums {
            m: self.m - o.m,
            mc: self.mc - o.mc,
            mcc: self.mcc - o.mcc,
            i: self.i - o.i,
        }
    }

    /// Mean inertia about `p`: `Σ I_mean + ⅔·Σ m·|c − p|²`.
    fn load(&self, p: &Vector3<f64>) -> stiffness::JointLoad {
        let spread = self.mcc - 2.0 * p.dot(&self.mc) + self.m * p.norm_squared();
        stiffness::JointLoad {
            mass: self.m.max(0.0),
            inertia: (self.i + 2.0 / 3.0 * spread.max(0.0)).max(0.0),
            anchor_distance: p.norm(),
        }
    }
}

/// No node / not a tree edge.
const NONE: usize = usize::MAX;

/// The bodies and joints as a graph: node 0 = the ground (every body that is not dynamic),
/// then every dynamic body of a joint with its mass sums; one edge per joint (`None` for a
/// joint within one node or to a body that left the world).
struct LoadGraph {
    sums: Vec<Sums>,
    edges: Vec<Option<(usize, usize)>>,
    adj: Vec<Vec<(usize, usize)>>,
}

/// A depth-first search of a [`LoadGraph`] from the ground, then from every unreached body:
/// discovery times, low links (Tarjan's bridges), the mass sums of each subtree, the root
/// each node was reached from, and the child node of each tree edge ([`NONE`] otherwise).
struct Dfs {
    disc: Vec<usize>,
    low: Vec<usize>,
    sub: Vec<Sums>,
    root_of: Vec<usize>,
    child: Vec<usize>,
}

impl LoadGraph {
    fn new(joints: &[Kjoint], bodies: &RigidBodySet) -> Self {
        let mut node_of: HashMap<RigidBodyHandle, usize> = HashMap::new();
        let mut sums = vec![Sums::default()];
        let mut node = |hb: RigidBodyHandle| -> Option<usize> {
            let b = bodies.get(hb)?;
            if !b.is_dynamic() {
                return Some(0);
            }
            Some(*node_of.entry(hb).or_insert_with(|| {
                let c = from_vec3(b.center_of_mass());
                let m = b.mass() as f64;
                sums.push(Sums {
                    m,
                    mc: m * c,
                    mcc: m * c.norm_squared(),
                    i: mean_inertia(b),
                });
                sums.len() - 1
            }))
        };
        let mut edges: Vec<Option<(usize, usize)>> = Vec::with_capacity(joints.len());
        for j in joints {
            edges.push(match (node(j.body1), node(j.body2)) {
                (Some(a), Some(b)) if a != b => Some((a, b)),
                _ => None,
            });
        }
        let mut adj: Vec<Vec<(usize, usize)>> = vec![Vec::new(); sums.len()];
        for (e, ab) in edges.iter().enumerate() {
            if let Some((a, b)) = *ab {
                adj[a].push((b, e));
                adj[b].push((a, e));
            }
        }
        LoadGraph { sums, edges, adj }
    }

    /// Per node, the root of its island: the bodies linked through dynamic bodies only (the
    /// ground, node 0, is an island of its own).
    fn island_roots(&self) -> Vec<usize> {
        fn find(p: &mut [usize], mut x: usize) -> usize {
            while p[x] != x {
                p[x] = p[p[x]];
                x = p[x];
            }
            x
        }
        let n = self.sums.len();
        let mut island: Vec<usize> = (0..n).collect();
        for &(a, b) in self.edges.iter().flatten() {
            if a != 0 && b != 0 {
                let (ra, rb) = (find(&mut island, a), find(&mut island, b));
                island[ra] = rb;
            }
        }
        (0..n).map(|v| find(&mut island, v)).collect()
    }

    /// Per joint (in the order of `joints`, this graph's edges), whether its blocked
    /// stiffness is to be resolved: it is unresolved, or a joint of its island is.
    fn stale_joints(&self, joints: &[Kjoint]) -> Vec<bool> {
        let root = self.island_roots();
        let mut stale_island = vec![false; self.sums.len()];
        for (j, ab) in joints.iter().zip(&self.edges) {
            if let (None, Some((a, b))) = (j.blocked, ab) {
                for v in [*a, *b].into_iter().filter(|v| *v != 0) {
                    stale_island[root[v]] = true;
                }
            }
        }
        joints
            .iter()
            .zip(&self.edges)
            .map(|(j, ab)| {
                j.blocked.is_none()
                    || ab.is_some_and(|(a, b)| {
                        [a, b].iter().any(|v| *v != 0 && stale_island[root[*v]])
                    })
            })
            .collect()
    }

    /// Per node, the mass sums of its island: the bodies linked through dynamic bodies only
    /// (a loop joint carries its island).
    fn island_sums(&self) -> Vec<Sums> {
        let n = self.sums.len();
        let root = self.island_roots();
        let mut by_root = vec![Sums::default(); n];
        for v in 1..n {
            let s = self.sums[v];
            by_root[root[v]].add(&s);
        }
        (0..n).map(|v| by_root[root[v]]).collect()
    }

    /// The iterative depth-first search ([`Dfs`]).
    fn bridges(&self) -> Dfs {
        let n = self.sums.len();
        let mut d = Dfs {
            disc: vec![NONE; n],
            low: vec![0usize; n],
            sub: self.sums.clone(),
            root_of: vec![0usize; n],
            child: vec![NONE; self.edges.len()],
        };
        let mut time = 0;
        let mut stack: Vec<(usize, usize, usize)> = Vec::new(); // (node, parent edge, next)
        for r in 0..n {
            if d.disc[r] != NONE {
                continue;
            }
            d.disc[r] = time;
            d.low[r] = time;
            time += 1;
            d.root_of[r] = r;
            stack.push((r, NONE, 0));
            while let Some(top) = stack.last_mut() {
                let (v, pe, next) = *top;
                if let Some(&(w, e)) = self.adj[v].get(next) {
                    top.2 += 1;
                    if e == pe {
                        continue;
                    }
                    if d.disc[w] == NONE {
                        d.disc[w] = time;
                        d.low[w] = time;
                        time += 1;
                        d.root_of[w] = r;
                        d.child[e] = w;
                        stack.push((w, e, 0));
                    } else {
                        d.low[v] = d.low[v].min(d.disc[w]);
                    }
                } else {
                    stack.pop();
                    if let Some(&(p, _, _)) = stack.last() {
                        d.low[p] = d.low[p].min(d.low[v]);
                        let s = d.sub[v];
                        d.sub[p].add(&s);
                    }
                }
            }
        }
        d
    }
}

impl KjointSet {
    /// Before the set's first step: every dynamic jointed body's pose and velocity are
    /// finite, else the error names the joint, the body and what is not finite. (The first
    /// step's zero-length rapier step, [`KjointSet::prepare`], would quarantine such a body,
    /// zeroing its velocity and disabling it, and the stiffness rule then read it as a body
    /// without mass: "automatic stiffness is zero: a body has no mass", a mechanism
    /// designer's trial, 2026-12-05.) Later the gather stage checks each body as it reads it.
    pub(in crate::dynamics) fn check_bodies_before_start(
        &self,
        bodies: &RigidBodySet,
    ) -> Result<(), SimError> {
        for j in &self.joints {
            for (which, hb) in [(1, j.body1), (2, j.body2)] {
                let Some(b) = bodies.get(hb).filter(|b| b.is_dynamic()) else {
                    continue;
                };
                if !crate::dynamics::substep::pose_is_finite(b) {
                    return Err(SimError::InvalidJoint {
                        joint: j.name.clone(),
                        reason: format!("body {which} {}", non_finite_state(b)),
                    });
                }
            }
        }
        Ok(())
    }
}

/// A dynamic body of joint `j` (`which`: 1 or 2) has a finite mass >= 0 and finite principal
/// moments of inertia >= 0 (round-off below 0 allowed): rapier takes any value it is given
/// (`additional_mass(-1.0)`, a NaN mass), and the joint's update with a negative or NaN one
/// either ran silently on it or failed as a matrix "not positive definite".
fn check_body_mass(j: &Kjoint, which: u8, b: &RigidBody) -> Result<(), SimError> {
    if !b.is_dynamic() {
        return Ok(());
    }
    let m = b.mass() as f64;
    if !(m.is_finite() && m >= 0.0) {
        return Err(SimError::InvalidJoint {
            joint: j.name.clone(),
            reason: format!("body {which} has mass {m}: expected a finite mass >= 0 [kg]"),
        });
    }
    let i = from_vec3(b.mass_properties().local_mprops.principal_inertia());
    let tol = 1e-6 * i.amax();
    if !(i.iter().all(|v| v.is_finite()) && i.min() >= -tol) {
        return Err(SimError::InvalidJoint {
            joint: j.name.clone(),
            reason: format!(
                "body {which} has principal moments of inertia [{}, {}, {}]: expected finite \
                 values >= 0 [kg·m²]",
                i.x, i.y, i.z
            ),
        });
    }
    Ok(())
}

/// A body's mass, mean inertia and anchor offset for the Radioss rule; a fixed body's offset
/// counted where `fixed_offset` (the property's rule is Radioss': §5), else 0.
fn body_mass(b: &RigidBody, local_anchor: &nalgebra::Vector3<f64>, fixed_offset: bool) -> BodyMass {
    let com = from_vec3(b.mass_properties().local_mprops.local_com);
    let anchor_offset_sq = (local_anchor - com).norm_squared();
    if !b.is_dynamic() {
        // a fixed body does not bound the automatic stiffness; its offset counts in r² (§5)
        // under the Radioss rule only (`fixed_offset`)
        return BodyMass::fixed(if fixed_offset { anchor_offset_sq } else { 0.0 });
    }
    BodyMass {
        mass: b.mass() as f64,
        inertia: mean_inertia(b),
        anchor_offset_sq,
    }
}

/// What of a body's state is not finite, as an error's words: "has a non-finite translation
/// [x, y, z] and linear velocity [..]: expected finite values (NaN or an infinity was set on
/// the rapier body)".
pub(crate) fn non_finite_state(b: &RigidBody) -> String {
    let v3 = |v: crate::rapier::math::Vector| [v.x, v.y, v.z];
    let q = b.rotation();
    let quat = [q.x, q.y, q.z, q.w];
    let finite = |v: &[crate::rapier::math::Real]| v.iter().all(|x| x.is_finite());
    let mut parts = Vec::new();
    for (name, v) in [
        ("translation", v3(b.translation()).to_vec()),
        ("rotation", quat.to_vec()),
        ("centre of mass", v3(b.center_of_mass()).to_vec()),
        ("linear velocity", v3(b.linvel()).to_vec()),
        ("angular velocity", v3(b.angvel()).to_vec()),
        ("user force", v3(b.user_force()).to_vec()),
        ("user torque", v3(b.user_torque()).to_vec()),
    ] {
        if !finite(&v) {
            parts.push(format!("{name} {v:?}"));
        }
    }
    if parts.is_empty() {
        // finite entries whose quaternion is zero or overflows its norm
        parts.push(format!("rotation {quat:?}"));
    }
    format!(
        "has a non-finite {}: expected finite values (NaN or an infinity set on the rapier \
         body, or a force that diverged)",
        parts.join(" and ")
    )
}
