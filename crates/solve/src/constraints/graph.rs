//! The part/constraint graph: biconnected blocks (only closed loops can hold redundant
//! equations) and connectivity to ground.
//!
//! Vertices are ground (0) and the moving parts (1..=n); every constraint element is an edge
//! between the bodies it connects (a clique when it touches more than two, e.g. a coupler —
//! a clique of three or more vertices is biconnected, so an element never straddles blocks).
//! Cost: O(V + E), iterative (no recursion, so chains of any length are fine).

use linkage_model::{Body, ConstraintKind, Model};

/// A biconnected block: elements and the moving parts they touch.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Block {
    /// Constraint indices, ascending.
    pub elements: Vec<usize>,
    /// Moving-part indices, ascending.
    pub parts: Vec<usize>,
}

/// Blocks and connectivity of a model's constraint graph.
#[derive(Clone, Debug, Default)]
pub struct Topology {
    pub blocks: Vec<Block>,
    /// Number of elements touching each part.
    pub degree: Vec<usize>,
    /// Whether each part is connected (through any chain of elements) to ground.
    pub grounded: Vec<bool>,
}

fn vertex(b: Body) -> usize {
    match b {
        Body::Ground => 0,
        Body::Part(k) => k + 1,
    }
}

/// Bodies an element connects. For a general constraint these are the bodies of every marker
/// its expression measures or orients (literal ids, [`crate::physics::measures::referenced_markers`]),
/// its I marker and ground; when an id is computed, all parts (the element then joins
/// everything in one block, which is always correct).
pub fn element_bodies(model: &Model, e: usize) -> Vec<Body> {
    let ConstraintKind::Gcon {
        expr: Some(parsed), ..
    } = &model.constraints[e].kind
    else {
        return model.constraint_bodies(e);
    };
    let mut bodies = model.constraint_bodies(e);
    let Ok(expr) = parsed else {
        return bodies;
    };
    let Some(ids) = crate::physics::measures::referenced_markers(expr) else {
        return std::iter::once(Body::Ground)
            .chain((0..model.parts.len()).map(Body::Part))
            .collect();
    };
    for id in ids {
        if let Some(m) = model.markers.iter().find(|m| m.id == u64::from(id)) {
            if !bodies.contains(&m.body) {
                bodies.push(m.body);
            }
        }
    }
    bodies
}

/// Builds the topology from `elements` (indices into `model.constraints`; inactive elements are
/// simply left out).
pub fn topology(model: &Model, elements: &[usize]) -> Topology {
    let nv = model.parts.len() + 1;
    // Edge list: (u, v, element).
    let mut edges: Vec<(usize, usize, usize)> = Vec::new();
    let mut degree = vec![0usize; model.parts.len()];
    for &e in elements {
        let bodies = element_bodies(model, e);
        for b in &bodies {
            if let Body::Part(k) = b {
                degree[*k] += 1;
            }
        }
        let vs: Vec<usize> = bodies.iter().map(|b| vertex(*b)).collect();
        match vs.len() {
            0 => {}
            1 => edges.push((vs[0], 0, e)),
            _ => {
                for a in 0..vs.len() {
                    for b in a + 1..vs.len() {
                        edges.push((vs[a], vs[b], e));
                    }
                }
            }
        }
    }
    // Adjacency (CSR).
    let mut start = vec![0usize; nv + 1];
    for &(u, v, _) in &edges {
        start[u + 1] += 1;
        start[v + 1] += 1;
    }
    for k in 0..nv {
        start[k + 1] += start[k];
    }
    let mut fill = start.clone();
    let mut adj = vec![(0usize, 0usize); start[nv]];
    for (ei, &(u, v, _)) in edges.iter().enumerate() {
        adj[fill[u]] = (v, ei);
        fill[u] += 1;
        adj[fill[v]] = (u, ei);
        fill[v] += 1;
    }

    // Iterative Hopcroft–Tarjan with an edge stack.
    let mut disc = vec![0usize; nv];
    let mut low = vec![0usize; nv];
    let mut time = 0usize;
    let mut edge_block = vec![usize::MAX; edges.len()];
    let mut nblocks = 0usize;
    let mut edge_stack: Vec<usize> = Vec::new();
    // Frame: (vertex, parent edge, next adjacency position).
    let mut frames: Vec<(usize, usize, usize)> = Vec::new();
    for root in 0..nv {
        if disc[root] != 0 {
            continue;
        }
        time += 1;
        disc[root] = time;
        low[root] = time;
        frames.push((root, usize::MAX, start[root]));
        while let Some(&mut (v, pe, ref mut pos)) = frames.last_mut() {
            if *pos < start[v + 1] {
                let (w, ei) = adj[*pos];
                *pos += 1;
                if ei == pe {
                    continue;
                }
                if w == v {
                    // Self loop: its own block.
                    edge_block[ei] = nblocks;
                    nblocks += 1;
                } else if disc[w] == 0 {
                    edge_stack.push(ei);
                    time += 1;
                    disc[w] = time;
                    low[w] = time;
                    frames.push((w, ei, start[w]));
                } else if disc[w] < disc[v] {
                    edge_stack.push(ei);
                    low[v] = low[v].min(disc[w]);
                }
            } else {
                frames.pop();
                if let Some(&(u, _, _)) = frames.last() {
                    low[u] = low[u].min(low[v]);
                    if low[v] >= disc[u] {
                        while let Some(x) = edge_stack.pop() {
                            edge_block[x] = nblocks;
                            if x == pe {
                                break;
                            }
                        }
                        nblocks += 1;
                    }
                }
            }
        }
    }
    let mut blocks = vec![Block::default(); nblocks];
    for (ei, &(u, v, e)) in edges.iter().enumerate() {
        let b = edge_block[ei];
        if b == usize::MAX {
            continue;
        }
        let blk = &mut blocks[b];
        if blk.elements.last() != Some(&e) {
            blk.elements.push(e);
        }
        for x in [u, v] {
            if x > 0 {
                blk.parts.push(x - 1);
            }
        }
    }
    for blk in &mut blocks {
        blk.elements.sort_unstable();
        blk.elements.dedup();
        blk.parts.sort_unstable();
        blk.parts.dedup();
    }
    blocks.retain(|b| !b.elements.is_empty());

    // Connectivity to ground (union–find).
    let mut parent: Vec<usize> = (0..nv).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    for &(u, v, _) in &edges {
        let (a, b) = (find(&mut parent, u), find(&mut parent, v));
        if a != b {
            parent[a] = b;
        }
    }
    let g = find(&mut parent, 0);
    let grounded = (1..nv).map(|x| find(&mut parent, x) == g).collect();
    Topology {
        blocks,
        degree,
        grounded,
    }
}
