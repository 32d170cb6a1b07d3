//! The assembly tree: parts that own bodies and place other parts.

use crate::topology::Wire;
use crate::{EdgeId, FaceId, MeshId, Model, PartId, ShellId, SolidId, Style};
use cadre_geom::{Transform, Vec3};

/// A piece of geometry a part owns, in the part's own coordinates.
#[derive(Clone, Debug, PartialEq)]
pub enum Body {
    /// A solid (`MANIFOLD_SOLID_BREP`, `BREP_WITH_VOIDS`, `FACETED_BREP`).
    Solid(SolidId),
    /// A shell outside any solid (surface models).
    Shell(ShellId),
    /// A face outside any shell.
    Face(FaceId),
    /// A tessellated item.
    Mesh(MeshId),
    /// An edge alone (edge-based wireframe), bounded by its vertices.
    Edge(EdgeId),
    /// A curve alone (wireframe curve sets).
    Wire(Wire),
    /// A point alone.
    Point(Vec3),
}

/// A placed use of a part inside another part.
#[derive(Clone, Debug, PartialEq)]
pub struct Occurrence {
    /// The part placed.
    pub part: PartId,
    /// Child coordinates → parent coordinates (mm).
    pub transform: Transform,
    /// Occurrence name (the `NEXT_ASSEMBLY_USAGE_OCCURRENCE` name or id), may be empty.
    pub name: String,
    /// STEP instance id of the occurrence (`NEXT_ASSEMBLY_USAGE_OCCURRENCE` or `MAPPED_ITEM`).
    pub step_id: u64,
}

/// A part: a product definition, or a representation used through a mapped item.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Part {
    /// Display name (product name, else representation name).
    pub name: String,
    /// Product id (part number), empty for a representation.
    pub product_id: String,
    /// Whether it comes from a product definition (rather than a bare representation).
    pub is_product: bool,
    /// Geometry owned directly.
    pub bodies: Vec<Body>,
    /// Placed sub-parts.
    pub children: Vec<Occurrence>,
    /// Appearance given to the part as a whole.
    pub style: Option<Style>,
    /// STEP instance id (`PRODUCT_DEFINITION` or representation).
    pub step_id: u64,
}

/// One visit of a part during a walk of the assembly tree from the roots.
#[derive(Clone, Copy, Debug)]
pub struct InstanceVisit {
    /// The part visited.
    pub part: PartId,
    /// Part coordinates → world coordinates.
    pub transform: Transform,
    /// Depth below the root (0 for a root).
    pub depth: usize,
}

/// Assembly trees deeper than this are cut by the mapper, with a warning naming the part
/// where the cut is; real assemblies are a few dozen levels deep at most, and every walk of
/// the tree is iterative, so the cap only bounds pathological files (a 300-level chain
/// loads whole).
pub const MAX_ASSEMBLY_DEPTH: usize = 1024;

impl Model {
    /// Visits every part instance reachable from the roots, depth first, with its world
    /// transform. A part used `n` times is visited `n` times.
    pub fn visit_instances(&self, mut f: impl FnMut(InstanceVisit)) {
        let mut stack: Vec<InstanceVisit> = self
            .roots
            .iter()
            .rev()
            .map(|&part| InstanceVisit {
                part,
                transform: Transform::IDENTITY,
                depth: 0,
            })
            .collect();
        while let Some(visit) = stack.pop() {
            f(visit);
            if visit.depth >= MAX_ASSEMBLY_DEPTH {
                continue;
            }
            let Some(part) = self.parts.get(visit.part.index()) else {
                continue;
            };
            for occ in part.children.iter().rev() {
                stack.push(InstanceVisit {
                    part: occ.part,
                    transform: visit.transform * occ.transform,
                    depth: visit.depth + 1,
                });
            }
        }
    }

    /// How many placed instances of parts with bodies the roots expand to (what a renderer
    /// draws one record for), counted over the part graph without expanding it: each part's
    /// count is computed once, so 2·10⁶ instances are counted in microseconds. Saturates at
    /// `u64::MAX`; a cycle (which the STEP mapper breaks) counts as nothing below it.
    pub fn placed_body_instances(&self) -> u64 {
        self.count_instances(|part| u64::from(!part.bodies.is_empty()))
    }

    /// How many part instances (with bodies or not: every node an exported tree has) the
    /// roots expand to, counted like [`Model::placed_body_instances`].
    pub fn placed_instances(&self) -> u64 {
        self.count_instances(|_| 1)
    }

    /// Sum over every instance reachable from the roots of `weight` of its part, computed
    /// once per part.
    fn count_instances(&self, weight: impl Fn(&Part) -> u64) -> u64 {
        // Per part: None = not visited, Some(None) = being counted, Some(Some(n)) = done.
        let mut count: Vec<Option<Option<u64>>> = vec![None; self.parts.len()];
        let mut total: u64 = 0;
        for root in &self.roots {
            let mut stack = vec![(root.index(), false)];
            while let Some((p, children_done)) = stack.pop() {
                let Some(part) = self.parts.get(p) else {
                    continue;
                };
                if children_done {
                    let own = weight(part);
                    let below = part.children.iter().fold(own, |acc, o| {
                        let c = count.get(o.part.index()).copied().flatten().flatten();
                        acc.saturating_add(c.unwrap_or(0))
                    });
                    count[p] = Some(Some(below));
                    continue;
                }
                if count[p].is_some() {
                    continue;
                }
                count[p] = Some(None);
                stack.push((p, true));
                for o in &part.children {
                    if count.get(o.part.index()).is_some_and(Option::is_none) {
                        stack.push((o.part.index(), false));
                    }
                }
            }
            let n = count[root.index()].flatten().unwrap_or(0);
            total = total.saturating_add(n);
        }
        total
    }

    /// The part with this id.
    pub fn part(&self, id: PartId) -> &Part {
        &self.parts[id.index()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_geom::Vec3;

    /// A root placing part 1 twice; part 1 placing part 2 once, translated.
    fn tree() -> Model {
        let shift = |x: f64| Transform::from_translation(Vec3::new(x, 0.0, 0.0));
        let occ = |part: u32, x: f64| Occurrence {
            part: PartId(part),
            transform: shift(x),
            name: String::new(),
            step_id: 0,
        };
        Model {
            parts: vec![
                Part {
                    children: vec![occ(1, 10.0), occ(1, 20.0)],
                    ..Part::default()
                },
                Part {
                    children: vec![occ(2, 1.0)],
                    ..Part::default()
                },
                Part {
                    bodies: vec![Body::Point(Vec3::ZERO)],
                    ..Part::default()
                },
            ],
            roots: vec![PartId(0)],
            ..Model::default()
        }
    }

    #[test]
    fn instances_are_visited_once_per_path_with_composed_transforms() {
        let m = tree();
        let mut leaves = Vec::new();
        m.visit_instances(|v| {
            if v.part == PartId(2) {
                leaves.push(v.transform.transform_point3(Vec3::ZERO).x);
            }
        });
        assert_eq!(leaves, vec![11.0, 21.0]);
        assert_eq!(m.counts().instances, 2);
        let b = m.bbox(cadre_geom::Accuracy::default());
        assert_eq!((b.min.x, b.max.x), (11.0, 21.0));
    }

    /// The count without expansion agrees with the expanding walk, on the small tree and on a
    /// wide one (six levels of ten uses: 10⁶ leaves) that the walk would take long to expand.
    #[test]
    fn placed_body_instances_are_counted_without_expanding() {
        let m = tree();
        let mut walked = 0;
        m.visit_instances(|v| walked += u64::from(!m.part(v.part).bodies.is_empty()));
        assert_eq!((m.placed_body_instances(), walked), (2, 2));
        assert_eq!(
            m.placed_instances(),
            5,
            "root, two of part 1, two of part 2"
        );

        // Negative control: a part placed but without bodies counts nothing.
        let mut bare = tree();
        bare.parts[2].bodies.clear();
        assert_eq!(bare.placed_body_instances(), 0);

        let mut wide = Model::default();
        wide.parts.push(Part {
            bodies: vec![Body::Point(Vec3::ZERO)],
            ..Part::default()
        });
        for level in 0..6u32 {
            let occ = Occurrence {
                part: PartId(level),
                transform: Transform::IDENTITY,
                name: String::new(),
                step_id: 0,
            };
            wide.parts.push(Part {
                children: vec![occ; 10],
                ..Part::default()
            });
        }
        wide.roots = vec![PartId(6)];
        assert_eq!(wide.placed_body_instances(), 1_000_000);
    }
}
