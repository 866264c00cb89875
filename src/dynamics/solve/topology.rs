//! Structure of the joint system, analysed once per topology change (a joint inserted or
//! removed, a body switching between dynamic and fixed or removed), never per substep.
//!
//! The unknowns of the implicit update are one impulse per joint and one velocity change per
//! dynamic body. Joints and dynamic bodies form a bipartite graph (a joint is linked to each
//! of its dynamic bodies; fixed and kinematic bodies are not nodes). Its connected
//! components are the **islands**: they are solved independently. An island with `V` nodes
//! and `E` links is a tree exactly when `E = V − 1`; then it is eliminated leaves first
//! (no fill whatever the insertion order, a hub included), the bodies with one child joint
//! (links) in the joint-space form and the others in the body + joint form ([`super::tree`]);
//! which bodies are links is decided here. An island with loops goes to a sparse
//! factorisation whose ordering and symbolic analysis are made here too
//! ([`super::loops`]); the joints that close its loops are listed for diagnostics.

/// A node of a tree island, in elimination order (children before parents).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct TreeNode {
    /// What the node is.
    pub kind: NodeKind,
    /// Position of the parent node in the island's node list (`u32::MAX`: the root).
    pub parent: u32,
    /// Side (0: body 1, 1: body 2) of the joint of the link to the parent: the joint is
    /// this node or the parent, whichever is a joint.
    pub side: u8,
    /// A body node with exactly one child joint (a chain's interior body): eliminated in the
    /// joint-space form together with that joint ([`super::tree`]). Always `false` for
    /// joints, leaves (no child joint) and hubs (several).
    pub link: bool,
}

/// The unknown a tree node carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum NodeKind {
    /// The impulse of joint `j` (global joint index).
    Joint(u32),
    /// The velocity change of solver body `b` (global body index).
    Body(u32),
}

/// How an island is solved.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Plan {
    /// Leaves-first block elimination over these nodes.
    Tree(Vec<TreeNode>),
    /// Sparse factorisation; the joints that close loops (global indices).
    Loops { closing: Vec<u32> },
}

/// One island: its joints and bodies (global indices, ascending) and how it is solved.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct IslandPlan {
    pub joints: Vec<u32>,
    pub bodies: Vec<u32>,
    pub plan: Plan,
}

fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let p = parent[x as usize];
        parent[x as usize] = parent[p as usize];
        x = p;
    }
    x
}

/// The union–find root of every solver body, the bodies linked by joints with both sides
/// dynamic (`sides` as in [`analyse`]): one root per island.
pub(crate) fn body_roots(n_bodies: usize, sides: &[[Option<u32>; 2]]) -> Vec<u32> {
    let mut uf: Vec<u32> = (0..n_bodies as u32).collect();
    for s in sides {
        if let [Some(a), Some(b)] = *s {
            let (ra, rb) = (find(&mut uf, a), find(&mut uf, b));
            if ra != rb {
                uf[ra as usize] = rb;
            }
        }
    }
    (0..n_bodies as u32).map(|b| find(&mut uf, b)).collect()
}

/// Splits the joints into islands and plans each one. `sides[j]` holds the solver bodies of
/// joint `j` (`None`: not dynamic); joints with `active[j] == false` are left out.
pub(crate) fn analyse(
    n_bodies: usize,
    sides: &[[Option<u32>; 2]],
    active: &[bool],
) -> Vec<IslandPlan> {
    // union-find over bodies; a joint closing a cycle is a loop joint
    let mut uf: Vec<u32> = (0..n_bodies as u32).collect();
    let mut closing = Vec::new();
    for (j, s) in sides.iter().enumerate() {
        if !active[j] {
            continue;
        }
        if let [Some(a), Some(b)] = *s {
            let (ra, rb) = (find(&mut uf, a), find(&mut uf, b));
            if ra == rb {
                closing.push(j as u32);
            } else {
                uf[ra as usize] = rb;
            }
        }
    }
    // islands in the order of their first joint
    let mut island_of_root = vec![u32::MAX; n_bodies];
    let mut islands: Vec<IslandPlan> = Vec::new();
    for (j, s) in sides.iter().enumerate() {
        if !active[j] {
            continue;
        }
        let body = s[0].or(s[1]);
        let idx = match body {
            None => {
                islands.push(IslandPlan {
                    joints: Vec::new(),
                    bodies: Vec::new(),
                    plan: Plan::Tree(Vec::new()),
                });
                islands.len() - 1
            }
            Some(b) => {
                let r = find(&mut uf, b) as usize;
                if island_of_root[r] == u32::MAX {
                    island_of_root[r] = islands.len() as u32;
                    islands.push(IslandPlan {
                        joints: Vec::new(),
                        bodies: Vec::new(),
                        plan: Plan::Tree(Vec::new()),
                    });
                }
                island_of_root[r] as usize
            }
        };
        islands[idx].joints.push(j as u32);
    }
    for b in 0..n_bodies as u32 {
        let r = find(&mut uf, b) as usize;
        if island_of_root[r] != u32::MAX {
            islands[island_of_root[r] as usize].bodies.push(b);
        }
    }
    for c in closing {
        let b = sides[c as usize][0].expect("a closing joint links two bodies");
        let r = find(&mut uf, b) as usize;
        let island = &mut islands[island_of_root[r] as usize];
        match &mut island.plan {
            Plan::Loops { closing } => closing.push(c),
            plan => *plan = Plan::Loops { closing: vec![c] },
        }
    }
    for island in &mut islands {
        if matches!(island.plan, Plan::Tree(_)) {
            island.plan = Plan::Tree(leaves_first(island, sides));
        }
    }
    islands
}

/// Post-order of a tree island from its first joint: every node comes after all of its
/// children, so eliminating in this order never creates fill (the coupling a link's
/// elimination makes between its two joints is the tree edge joint–link–joint contracted).
/// Bodies with exactly one child joint are marked as links.
fn leaves_first(island: &IslandPlan, sides: &[[Option<u32>; 2]]) -> Vec<TreeNode> {
    let nj = island.joints.len();
    let nb = island.bodies.len();
    // local node ids: joints 0..nj, bodies nj..nj+nb; adjacency in compressed rows
    let local_body = |b: u32| nj + island.bodies.binary_search(&b).expect("body of the island");
    let mut degree = vec![0usize; nj + nb];
    for (lj, &j) in island.joints.iter().enumerate() {
        for b in sides[j as usize].iter().flatten() {
            degree[lj] += 1;
            degree[local_body(*b)] += 1;
        }
    }
    let mut start = vec![0usize; nj + nb + 1];
    for i in 0..nj + nb {
        start[i + 1] = start[i] + degree[i];
    }
    let mut fill = start.clone();
    // (neighbour, side of the joint of this link)
    let mut adj = vec![(0usize, 0u8); start[nj + nb]];
    for (lj, &j) in island.joints.iter().enumerate() {
        for (side, b) in sides[j as usize].iter().enumerate() {
            if let Some(b) = b {
                let lb = local_body(*b);
                adj[fill[lj]] = (lb, side as u8);
                fill[lj] += 1;
                adj[fill[lb]] = (lj, side as u8);
                fill[lb] += 1;
            }
        }
    }
    let node_kind = |n: usize| {
        if n < nj {
            NodeKind::Joint(island.joints[n])
        } else {
            NodeKind::Body(island.bodies[n - nj])
        }
    };
    // iterative depth-first search: (node, parent, side, next neighbour to visit)
    let mut order: Vec<(usize, usize, u8)> = Vec::with_capacity(nj + nb);
    let mut stack: Vec<(usize, usize, u8, usize)> = vec![(0, usize::MAX, 0, start[0])];
    while let Some(top) = stack.last_mut() {
        let (node, parent, side, next) = *top;
        if next < start[node + 1] {
            top.3 += 1;
            let (nb_node, nb_side) = adj[next];
            if nb_node != parent {
                stack.push((nb_node, node, nb_side, start[nb_node]));
            }
        } else {
            order.push((node, parent, side));
            stack.pop();
        }
    }
    debug_assert_eq!(order.len(), nj + nb, "a tree island is connected");
    let mut position = vec![u32::MAX; nj + nb];
    // child joints of every body (a joint's parent is a body or nothing)
    let mut children = vec![0u32; nj + nb];
    for (i, &(node, parent, _)) in order.iter().enumerate() {
        position[node] = i as u32;
        if parent != usize::MAX {
            children[parent] += 1;
        }
    }
    order
        .iter()
        .map(|&(node, parent, side)| TreeNode {
            kind: node_kind(node),
            parent: if parent == usize::MAX {
                u32::MAX
            } else {
                position[parent]
            },
            side,
            link: node >= nj && children[node] == 1,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(n: usize) -> Vec<bool> {
        vec![true; n]
    }

    #[test]
    fn a_chain_is_one_tree_eliminated_children_first() {
        // world - j0 - b0 - j1 - b1 - j2 - b2
        let sides = [[None, Some(0)], [Some(0), Some(1)], [Some(1), Some(2)]];
        let islands = analyse(3, &sides, &all(3));
        assert_eq!(islands.len(), 1);
        let Plan::Tree(nodes) = &islands[0].plan else {
            panic!("a chain has no loop")
        };
        assert_eq!(nodes.len(), 6);
        for (i, n) in nodes.iter().enumerate() {
            if n.parent != u32::MAX {
                assert!(n.parent as usize > i, "parent after child");
            }
        }
        assert_eq!(nodes.iter().filter(|n| n.parent == u32::MAX).count(), 1);
        // b0 and b1 are links, b2 (the free end) a leaf, the root a joint
        let links: Vec<_> = nodes.iter().filter(|n| n.link).map(|n| n.kind).collect();
        assert_eq!(links, vec![NodeKind::Body(1), NodeKind::Body(0)]);
        assert!(matches!(nodes[5].kind, NodeKind::Joint(0)));
    }

    #[test]
    fn a_hub_is_not_a_link() {
        // world - j0 - b0 (hub) - j1 - b1 - j3 - b3,  b0 - j2 - b2
        let sides = [
            [None, Some(0)],
            [Some(0), Some(1)],
            [Some(0), Some(2)],
            [Some(1), Some(3)],
        ];
        let islands = analyse(4, &sides, &all(4));
        let Plan::Tree(nodes) = &islands[0].plan else {
            panic!("no loop")
        };
        let link = |b: u32| {
            nodes
                .iter()
                .find(|n| n.kind == NodeKind::Body(b))
                .unwrap()
                .link
        };
        assert!(!link(0), "two child joints: a hub");
        assert!(link(1));
        assert!(!link(2) && !link(3), "leaves");
    }

    #[test]
    fn islands_loops_and_isolated_joints() {
        // island A: four-bar b0-b1-b2-b3-b0 (loop); island B: b4 on the world; joint 5: no body
        let sides = [
            [Some(0), Some(1)],
            [Some(1), Some(2)],
            [Some(2), Some(3)],
            [Some(3), Some(0)],
            [None, Some(4)],
            [None, None],
            [Some(4), Some(5)],
        ];
        let mut active = all(7);
        let islands = analyse(6, &sides, &active);
        assert_eq!(islands.len(), 3);
        assert_eq!(islands[0].joints, vec![0, 1, 2, 3]);
        assert_eq!(islands[0].plan, Plan::Loops { closing: vec![3] });
        assert_eq!(islands[1].joints, vec![4, 6]);
        assert_eq!(islands[1].bodies, vec![4, 5]);
        assert!(matches!(islands[1].plan, Plan::Tree(ref n) if n.len() == 4));
        assert_eq!(islands[2].joints, vec![5]);
        // detaching a joint of the loop makes the island a tree
        active[3] = false;
        let islands = analyse(6, &sides, &active);
        assert!(matches!(islands[0].plan, Plan::Tree(ref n) if n.len() == 7));
    }

    #[test]
    fn two_joints_between_the_same_bodies_are_a_loop() {
        let sides = [[Some(0), Some(1)], [Some(0), Some(1)]];
        let islands = analyse(2, &sides, &all(2));
        assert_eq!(islands[0].plan, Plan::Loops { closing: vec![1] });
    }
}
