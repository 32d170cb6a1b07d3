//! Where a scene's meshes are placed, factored for GPU instancing: a list of [`Run`]s, each a
//! mesh under one world placement, drawn once per local placement of its [`LocalList`].
//!
//! Small scenes get one run per instance, all sharing the identity list (one draw record per
//! placed mesh, as before). A scene whose instances outnumber [`FLAT_LIMIT`] is cut where a
//! shared node's subtree places at most [`MAX_LOCALS_PER_NODE`] meshes: that subtree is
//! expanded once into local lists (relative to the node's parent) and every visit of the node
//! is one run per mesh below it. Six assembly levels of ten uses (10⁶ cubes) become 10³ runs over 10 lists of 10³ locals, where one record per instance
//! needed 128 MB on the GPU and 2.4 GB on the CPU to build.

use glam::{DAffine3, DMat3};

use cadre_mesh::scene::{MAX_DEPTH, Scene};

use crate::layout::{DRAW_INSIDE_OUT, Local};

/// Instances a scene may have and still get one draw record each (32 MB of records).
pub const FLAT_LIMIT: usize = 1 << 18;

/// Most placements below one shared node expanded into local lists (its subtree places no
/// more meshes than this, so the node is where a factored scene is cut).
pub const MAX_LOCALS_PER_NODE: usize = 4096;

/// A mesh placed by `world`, drawn once per local placement of list `list`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Run {
    /// Index into the scene's meshes.
    pub mesh: usize,
    /// World placement of the run (the locals' frame).
    pub world: DAffine3,
    /// Scene instance number ([`Scene::instances`] order) of the run's first placement; each
    /// local adds its [`Local::offset`].
    pub instance: u32,
    /// Index into [`Placements::lists`].
    pub list: usize,
}

/// A range of [`Placements::locals`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct LocalList {
    /// First local.
    pub first: u32,
    /// Number of locals (at least 1).
    pub count: u32,
}

/// A scene's placements, factored: runs × their local lists.
#[derive(Clone, Debug)]
pub(crate) struct Placements {
    /// Every run, in scene instance order.
    pub runs: Vec<Run>,
    /// Local lists; list 0 is the identity alone.
    pub lists: Vec<LocalList>,
    /// Local placements of all lists.
    pub locals: Vec<Local>,
    /// Instances placed (runs × their list sizes): [`Scene::instances`]' count.
    pub instances: usize,
}

impl Placements {
    /// The placements of `scene`'s instances; `solid(mesh)` says whether a mesh is a closed
    /// solid (a mirroring local placement then turns its winding over).
    /// More than `flat_limit` instances are factored ([`FLAT_LIMIT`] for the renderer).
    pub fn new(scene: &Scene, solid: impl Fn(usize) -> bool, flat_limit: usize) -> Placements {
        let mut placements = Placements {
            runs: Vec::new(),
            lists: vec![LocalList { first: 0, count: 1 }],
            locals: vec![Local::IDENTITY],
            instances: 0,
        };
        match SubtreeCounts::new(scene) {
            Some(counts) if counts.total > flat_limit => {
                placements.factored(scene, &counts, &solid);
            }
            // Small, or a graph the counts cannot follow (a cycle, or deeper than the walk
            // goes): one run per instance, as the scene's own walk yields them.
            _ => placements.flat(scene),
        }
        placements
    }

    /// The local placements of `list`.
    pub fn list(&self, list: LocalList) -> &[Local] {
        &self.locals[list.first as usize..(list.first + list.count) as usize]
    }

    /// Places one instance of `mesh` by `world`: a run on the identity list.
    fn place(&mut self, mesh: usize, world: DAffine3) {
        self.runs.push(Run {
            mesh,
            world,
            instance: self.instances as u32,
            list: 0,
        });
        self.instances += 1;
    }

    /// One run per instance, every run on the identity list.
    fn flat(&mut self, scene: &Scene) {
        for (node, world) in scene.instances() {
            if let Some(mesh) = mesh_of(scene, node) {
                self.place(mesh, world);
            }
        }
    }

    /// Runs of the visits above the cut and local lists below it.
    fn factored(&mut self, scene: &Scene, counts: &SubtreeCounts, solid: &impl Fn(usize) -> bool) {
        // Per node: its lists (mesh, list) once expanded.
        let mut lists_of: Vec<Option<Vec<(usize, usize)>>> = vec![None; scene.nodes.len()];
        let mut stack: Vec<(usize, DAffine3)> = scene
            .roots
            .iter()
            .rev()
            .filter(|&&r| r < scene.nodes.len())
            .map(|&r| (r, DAffine3::IDENTITY))
            .collect();
        while let Some((node, parent_world)) = stack.pop() {
            let n = &scene.nodes[node];
            let below = counts.of[node];
            // A leaf stays a plain run: a list of one would cost a list per leaf.
            if below <= MAX_LOCALS_PER_NODE && !n.children.is_empty() {
                let lists = lists_of[node]
                    .get_or_insert_with(|| self.expand(scene, node, solid))
                    .clone();
                for (mesh, list) in lists {
                    self.runs.push(Run {
                        mesh,
                        world: parent_world,
                        instance: self.instances as u32,
                        list,
                    });
                }
                self.instances += below;
                continue;
            }
            let world = parent_world * n.transform;
            if let Some(mesh) = mesh_of(scene, node) {
                self.place(mesh, world);
            }
            for &child in n.children.iter().rev() {
                if child < scene.nodes.len() {
                    stack.push((child, world));
                }
            }
        }
    }

    /// Expands `node`'s subtree (its own transform included) into one local list per mesh,
    /// each local's offset its instance number within the subtree.
    fn expand(
        &mut self,
        scene: &Scene,
        node: usize,
        solid: &impl Fn(usize) -> bool,
    ) -> Vec<(usize, usize)> {
        let mut per_mesh: Vec<(usize, Vec<Local>)> = Vec::new();
        let mut number = 0u32;
        let mut stack = vec![(node, DAffine3::IDENTITY)];
        while let Some((at, parent)) = stack.pop() {
            let n = &scene.nodes[at];
            let world = parent * n.transform;
            if let Some(mesh) = mesh_of(scene, at) {
                let local = local(world, number, solid(mesh));
                match per_mesh.iter_mut().find(|(m, _)| *m == mesh) {
                    Some((_, list)) => list.push(local),
                    None => per_mesh.push((mesh, vec![local])),
                }
                number += 1;
            }
            for &child in n.children.iter().rev() {
                if child < scene.nodes.len() {
                    stack.push((child, world));
                }
            }
        }
        per_mesh
            .into_iter()
            .map(|(mesh, list)| {
                let first = self.locals.len() as u32;
                let count = list.len() as u32;
                self.locals.extend(list);
                self.lists.push(LocalList { first, count });
                (mesh, self.lists.len() - 1)
            })
            .collect()
    }
}

/// The matrix that carries normals through `linear`: its inverse transpose (mirrors
/// included); a singular map gets itself.
pub(crate) fn normal_matrix(linear: DMat3) -> DMat3 {
    if linear.determinant().abs() > 1e-300 {
        linear.inverse().transpose()
    } else {
        linear
    }
}

/// `m`'s columns as the GPU structs' `array<vec4<f32>, 3>` (w unused).
pub(crate) fn normal_columns(m: DMat3) -> [[f32; 4]; 3] {
    let n = m.as_mat3();
    [
        n.x_axis.extend(0.0).to_array(),
        n.y_axis.extend(0.0).to_array(),
        n.z_axis.extend(0.0).to_array(),
    ]
}

/// The valid mesh index of `node`, if any.
fn mesh_of(scene: &Scene, node: usize) -> Option<usize> {
    scene.nodes[node].mesh.filter(|&m| m < scene.meshes.len())
}

/// The local placement `world` (relative to its run), instance `offset` into the run, mirror
/// flag for a solid mesh.
fn local(world: DAffine3, offset: u32, solid: bool) -> Local {
    let linear: DMat3 = world.matrix3;
    Local {
        model: glam::DMat4::from(world).as_mat4().to_cols_array_2d(),
        normal: normal_columns(normal_matrix(linear)),
        offset,
        flags: if solid && linear.determinant() < 0.0 {
            DRAW_INSIDE_OUT
        } else {
            0
        },
        pad: [0; 2],
    }
}

/// Per node, how many meshes its subtree places (its own included), for a graph without
/// cycles and no deeper than the scene walk follows.
struct SubtreeCounts {
    of: Vec<usize>,
    total: usize,
}

impl SubtreeCounts {
    /// The counts, or `None` when the graph has a cycle, goes deeper than [`MAX_DEPTH`] or
    /// places more than `u32` numbers (the scene's own walk handles those cases).
    fn new(scene: &Scene) -> Option<SubtreeCounts> {
        const UNSEEN: usize = usize::MAX;
        const OPEN: usize = usize::MAX - 1;
        let len = scene.nodes.len();
        let mut of = vec![UNSEEN; len];
        let mut height = vec![0usize; len];
        for &root in &scene.roots {
            if root >= len || of[root] != UNSEEN {
                continue;
            }
            let mut stack = vec![(root, false)];
            while let Some((node, children_done)) = stack.pop() {
                let n = &scene.nodes[node];
                let children = n.children.iter().copied().filter(|&c| c < len);
                if children_done {
                    let own = usize::from(mesh_of(scene, node).is_some());
                    let mut count = own;
                    let mut h = 0;
                    for c in children {
                        count = count.saturating_add(of[c]);
                        h = h.max(height[c] + 1);
                    }
                    of[node] = count;
                    height[node] = h;
                    continue;
                }
                if of[node] == OPEN {
                    return None;
                }
                if of[node] != UNSEEN {
                    continue;
                }
                of[node] = OPEN;
                stack.push((node, true));
                for c in children {
                    match of[c] {
                        OPEN => return None,
                        UNSEEN => stack.push((c, false)),
                        _ => {}
                    }
                }
            }
        }
        let mut total = 0usize;
        for &root in scene.roots.iter().filter(|&&r| r < len) {
            if height[root] >= MAX_DEPTH {
                return None;
            }
            total = total.saturating_add(of[root]);
        }
        (total <= u32::MAX as usize).then_some(SubtreeCounts { of, total })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_mesh::scene::{SceneMesh, SceneNode};
    use glam::DVec3;

    /// `levels` levels of `uses` shared nodes above one leaf mesh: `uses^levels` instances,
    /// each level's uses spread along its own axis (and every other use mirrored).
    fn chain(levels: usize, uses: usize) -> Scene {
        let mut scene = Scene::default();
        scene.meshes.push(SceneMesh::default());
        // Level 0: the leaf nodes; level k's nodes have every node of level k-1 as children.
        let mut below: Vec<usize> = Vec::new();
        for level in 0..levels {
            let first = scene.nodes.len();
            for u in 0..uses {
                let mut offset = DVec3::ZERO;
                offset[level % 3] = (u as f64 + 1.0) * 10f64.powi(level as i32 / 3 + 1);
                let mirror = if u % 2 == 1 { -1.0 } else { 1.0 };
                scene.nodes.push(SceneNode {
                    transform: DAffine3::from_scale_rotation_translation(
                        DVec3::new(mirror, 1.0, 1.0),
                        glam::DQuat::IDENTITY,
                        offset,
                    ),
                    mesh: (level == 0).then_some(0),
                    children: below.clone(),
                    ..SceneNode::default()
                });
            }
            below = (first..first + uses).collect();
        }
        scene.nodes.push(SceneNode {
            children: below,
            ..SceneNode::default()
        });
        scene.roots.push(scene.nodes.len() - 1);
        scene
    }

    /// Every instance's (number, world, mirrored) from the placements, sorted by number.
    fn expanded(p: &Placements) -> Vec<(u32, DAffine3, bool)> {
        let mut out = Vec::new();
        for run in &p.runs {
            let list = p.lists[run.list];
            for l in &p.locals[list.first as usize..(list.first + list.count) as usize] {
                let local =
                    DAffine3::from_mat4(glam::Mat4::from_cols_array_2d(&l.model).as_dmat4());
                out.push((
                    run.instance + l.offset,
                    run.world * local,
                    l.flags & DRAW_INSIDE_OUT != 0,
                ));
            }
        }
        out.sort_by_key(|e| e.0);
        out
    }

    fn close(a: DAffine3, b: DAffine3) -> bool {
        a.abs_diff_eq(b, 1e-3 * (1.0 + b.translation.length()))
    }

    /// A factored scene places exactly the scene walk's instances, numbered in walk order.
    #[test]
    fn factored_placements_are_the_walks_instances() {
        let scene = chain(6, 9); // 531,441 instances: past FLAT_LIMIT
        let p = Placements::new(&scene, |_| true, FLAT_LIMIT);
        assert_eq!(p.instances, 9usize.pow(6));
        assert!(p.runs.len() <= 9usize.pow(3), "{} runs", p.runs.len());
        assert!(
            p.locals.len() <= 1 + 9 * 9usize.pow(3),
            "{} locals",
            p.locals.len()
        );
        let walk: Vec<DAffine3> = scene.instances().map(|(_, w)| w).collect();
        let placed = expanded(&p);
        assert_eq!(placed.len(), walk.len());
        for (k, (number, world, mirrored)) in placed.iter().enumerate() {
            assert_eq!(*number as usize, k);
            assert!(
                close(*world, walk[k]),
                "instance {k}: {world:?} vs {:?}",
                walk[k]
            );
            // The run's own mirror is the record's flag; the local's is relative to it.
            let run_mirrored = p
                .runs
                .iter()
                .rev()
                .find(|r| r.instance <= *number)
                .is_some_and(|r| r.world.matrix3.determinant() < 0.0);
            assert_eq!(
                *mirrored != run_mirrored,
                walk[k].matrix3.determinant() < 0.0,
                "instance {k}"
            );
        }
    }

    /// Negative control: a small scene is not factored (one run per instance on the identity
    /// list), and a misplaced local would be seen by the comparison above.
    #[test]
    fn small_scenes_get_one_run_per_instance() {
        let scene = chain(3, 4);
        let p = Placements::new(&scene, |_| true, FLAT_LIMIT);
        assert_eq!((p.instances, p.runs.len(), p.locals.len()), (64, 64, 1));
        assert!(p.runs.iter().all(|r| r.list == 0));
        let walk: Vec<DAffine3> = scene.instances().map(|(_, w)| w).collect();
        let placed = expanded(&p);
        assert!(placed.iter().zip(&walk).all(|(a, b)| close(a.1, *b)));
        let mut wrong = p.clone();
        wrong.runs[5].world.translation.x += 1.0;
        let placed = expanded(&wrong);
        assert!(!placed.iter().zip(&walk).all(|(a, b)| close(a.1, *b)));
    }

    /// A cycle falls back to the scene's own walk (which skips the recurring node).
    #[test]
    fn cycles_fall_back_to_the_walk() {
        let mut scene = chain(2, 3);
        let root = scene.roots[0];
        scene.nodes[0].children.push(root);
        let p = Placements::new(&scene, |_| true, FLAT_LIMIT);
        assert_eq!(p.instances, scene.instances().count());
    }
}
