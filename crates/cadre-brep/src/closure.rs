//! Whether shells are closed: edges used by one face only ("free" edges), and the connected
//! pieces of a shell. A solid whose shell has free edges bounds no volume.

use std::collections::HashMap;

use crate::topology::LoopKind;
use crate::{EdgeId, FaceId, Model, ShellId};
use cadre_geom::Accuracy;

impl Model {
    /// Whether an edge has no extent (a pole of a sphere, a cone apex written as an edge).
    pub fn is_degenerate_edge(&self, id: EdgeId, acc: Accuracy) -> bool {
        let edge = &self.edges[id.index()];
        let Some(curve) = edge.curve else { return true };
        if edge.start != edge.end {
            return false;
        }
        let p = self.vertices[edge.start.index()].point;
        let tol = acc.distance.max(1e-9 * (1.0 + p.abs().max_element())) * 100.0;
        let curve = &self.curves[curve.index()];
        match self.edge_range(id, acc) {
            Some((t0, t1)) => (0..=4).all(|i| {
                let t = t0 + (t1 - t0) * f64::from(i) / 4.0;
                (curve.eval(t) - p).length() <= tol
            }),
            None => true,
        }
    }

    /// Number of edges of `shell` used by exactly one face use (seams used twice by one face
    /// count as closed; degenerate edges are ignored).
    pub fn free_edges(&self, shell: ShellId, acc: Accuracy) -> usize {
        let mut uses: HashMap<EdgeId, u32> = HashMap::new();
        for &(face, _) in &self.shells[shell.index()].faces {
            for lp in &self.faces[face.index()].loops {
                if let LoopKind::Edges(es) = &lp.kind {
                    for oe in es {
                        *uses.entry(oe.edge).or_default() += 1;
                    }
                }
            }
        }
        uses.into_iter()
            .filter(|&(e, n)| n == 1 && !self.is_degenerate_edge(e, acc))
            .count()
    }

    /// The faces of `shell` grouped into pieces connected through shared edges, each with the
    /// orientation the shell uses it in.
    pub fn shell_components(&self, shell: ShellId) -> Vec<Vec<(FaceId, bool)>> {
        let faces = &self.shells[shell.index()].faces;
        let mut parent: Vec<usize> = (0..faces.len()).collect();
        fn find(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        let mut first_user: HashMap<EdgeId, usize> = HashMap::new();
        for (i, &(face, _)) in faces.iter().enumerate() {
            for lp in &self.faces[face.index()].loops {
                if let LoopKind::Edges(es) = &lp.kind {
                    for oe in es {
                        let j = *first_user.entry(oe.edge).or_insert(i);
                        let (a, b) = (find(&mut parent, i), find(&mut parent, j));
                        parent[a] = b;
                    }
                }
            }
        }
        let mut groups: HashMap<usize, Vec<(FaceId, bool)>> = HashMap::new();
        let mut order = Vec::new();
        for (i, &f) in faces.iter().enumerate() {
            let root = find(&mut parent, i);
            if !groups.contains_key(&root) {
                order.push(root);
            }
            groups.entry(root).or_default().push(f);
        }
        order
            .into_iter()
            .filter_map(|r| groups.remove(&r))
            .collect()
    }
}
