//! The box of a whole model: each placed part's box, from its faces' exact bounds.
//!
//! An instance whose transform keeps boxes axis-aligned takes its part's box, transformed. A
//! rotated instance is bounded tightly by the sample points of its part's faces, rotated.
//! Those samples used to be kept per part (for the life of the walk) and cost 4.7 MB of the
//! 10.3 MB heap peak of `cadre info` on the 3.5 MB `trj4_pm2-ec-214.stp`; now each face's
//! samples are folded, as soon as they are made, into one box per distinct rotation its part
//! is placed with, and dropped. A part placed in more than [`MAX_PART_ROTATIONS`] distinct
//! rotations keeps its samples instead, so the work stays bounded by samples × rotations.

use std::collections::HashMap;

use rayon::prelude::*;

use super::{EDGE_SAMPLES, curve_samples, edge_bounds, face_bounds, is_axis_aligned};
use crate::{Body, FaceId, Model, Part};
use cadre_geom::{Accuracy, BoundingBox, Transform, Vec3};

/// Most distinct rotations of one part bounded face by face; a part placed in more keeps its
/// sample points and rotates them per instance.
const MAX_PART_ROTATIONS: usize = 64;

/// The linear parts (rotation and scale) of one part's rotated instances, each once.
#[derive(Default)]
struct PartRotations {
    /// Whether any instance of the part is placed (unplaced parts are not bounded at all).
    placed: bool,
    /// Index in `linear` of each linear part, by its exact bits.
    index: HashMap<[u64; 9], usize>,
    /// The distinct linear parts, as transforms without translation.
    linear: Vec<Transform>,
    /// More than [`MAX_PART_ROTATIONS`] distinct ones: the part keeps its samples.
    overflow: bool,
}

fn linear_key(t: &Transform) -> [u64; 9] {
    t.matrix3.to_cols_array().map(f64::to_bits)
}

impl PartRotations {
    fn note(&mut self, t: &Transform) {
        self.placed = true;
        if is_axis_aligned(t) || self.overflow {
            return;
        }
        let key = linear_key(t);
        if self.index.contains_key(&key) {
            return;
        }
        if self.linear.len() == MAX_PART_ROTATIONS {
            self.overflow = true;
            return;
        }
        self.index.insert(key, self.linear.len());
        self.linear.push(Transform {
            matrix3: t.matrix3,
            translation: Vec3::ZERO,
        });
    }

    fn find(&self, t: &Transform) -> Option<usize> {
        self.index.get(&linear_key(t)).copied()
    }
}

/// What bounds one part's own bodies (children excluded), in part coordinates.
#[derive(Clone, Debug)]
struct PartExtent {
    /// The part's box.
    bbox: BoundingBox,
    /// The box of its samples under each of its distinct rotations (see [`PartRotations`]).
    rotated: Vec<BoundingBox>,
    /// Its sample points, kept only for a part with too many rotations.
    samples: Vec<Vec3>,
}

impl PartExtent {
    fn new(rotations: usize) -> Self {
        PartExtent {
            bbox: BoundingBox::EMPTY,
            rotated: vec![BoundingBox::EMPTY; rotations],
            samples: Vec::new(),
        }
    }

    /// Adds one body's box and its sample points.
    fn add(&mut self, b: &BoundingBox, samples: &[Vec3], rotations: &PartRotations) {
        self.bbox = self.bbox.union(b);
        for (r, t) in self.rotated.iter_mut().zip(&rotations.linear) {
            *r = r.union(&BoundingBox::from_points(
                samples
                    .iter()
                    .filter(|p| p.is_finite())
                    .map(|&p| t.transform_point3(p)),
            ));
        }
        if rotations.overflow {
            self.samples.extend_from_slice(samples);
        }
    }

    fn merge(mut self, other: PartExtent) -> PartExtent {
        self.bbox = self.bbox.union(&other.bbox);
        for (a, b) in self.rotated.iter_mut().zip(&other.rotated) {
            *a = a.union(b);
        }
        self.samples.extend(other.samples);
        self
    }
}

impl Model {
    /// The faces a part owns directly, through its solids, shells and loose faces.
    fn part_faces(&self, part: &Part) -> Vec<FaceId> {
        let mut faces = Vec::new();
        let shell = |id: crate::ShellId, faces: &mut Vec<FaceId>| {
            faces.extend(self.shells[id.index()].faces.iter().map(|&(f, _)| f));
        };
        for body in &part.bodies {
            match body {
                Body::Solid(id) => {
                    for s in self.solids[id.index()].shells() {
                        shell(s, &mut faces);
                    }
                }
                Body::Shell(id) => shell(*id, &mut faces),
                Body::Face(id) => faces.push(*id),
                _ => {}
            }
        }
        faces
    }

    /// The extent of one part's own bodies: faces in parallel, the other bodies after.
    fn part_extent(&self, part: &Part, rotations: &PartRotations, acc: Accuracy) -> PartExtent {
        let n = rotations.linear.len();
        let faces = self.part_faces(part);
        let mut extent = faces
            .par_iter()
            .fold(
                || PartExtent::new(n),
                |mut e, &f| {
                    let (b, samples) = face_bounds(self, &self.faces[f.index()], acc);
                    e.add(&b, &samples, rotations);
                    e
                },
            )
            .reduce(|| PartExtent::new(n), PartExtent::merge);
        for body in &part.bodies {
            match body {
                Body::Solid(_) | Body::Shell(_) | Body::Face(_) => {}
                Body::Mesh(id) => {
                    let mesh = &self.meshes[id.index()];
                    extent.add(&mesh.bbox(), &mesh.positions, rotations);
                }
                Body::Edge(e) => {
                    let mut samples = Vec::new();
                    let b = edge_bounds(self, *e, acc, &mut samples);
                    extent.add(&b, &samples, rotations);
                }
                Body::Wire(w) => {
                    let curve = &self.curves[w.curve.index()];
                    if let Some((t0, t1)) = w.range.or_else(|| curve.domain())
                        && t0.is_finite()
                        && t1.is_finite()
                    {
                        let samples: Vec<Vec3> =
                            curve_samples(curve, (t0, t1), EDGE_SAMPLES).collect();
                        extent.add(&curve.bbox_between(t0, t1), &samples, rotations);
                    }
                }
                Body::Point(p) => {
                    let mut b = BoundingBox::EMPTY;
                    b.add_point(*p);
                    extent.add(&b, &[*p], rotations);
                }
            }
        }
        extent
    }

    /// The world-space box of every part instance (empty for a model without geometry).
    pub fn bbox(&self, acc: Accuracy) -> BoundingBox {
        let mut rotations: Vec<PartRotations> = self
            .parts
            .iter()
            .map(|_| PartRotations::default())
            .collect();
        self.visit_instances(|visit| {
            if let Some(r) = rotations.get_mut(visit.part.index()) {
                r.note(&visit.transform);
            }
        });
        let extents: Vec<Option<PartExtent>> = self
            .parts
            .par_iter()
            .zip(&rotations)
            .map(|(part, r)| r.placed.then(|| self.part_extent(part, r, acc)))
            .collect();
        let mut b = BoundingBox::EMPTY;
        self.visit_instances(|visit| {
            let i = visit.part.index();
            let Some(Some(extent)) = extents.get(i) else {
                return;
            };
            if extent.bbox.is_empty() {
                return;
            }
            let t = &visit.transform;
            if is_axis_aligned(t) {
                b = b.union(&extent.bbox.transformed(t));
            } else if let Some(r) = rotations[i].find(t) {
                let shift = Transform::from_translation(t.translation);
                b = b.union(&extent.rotated[r].transformed(&shift));
            } else {
                b = b.union(&BoundingBox::from_points(
                    extent.samples.iter().map(|&p| t.transform_point3(p)),
                ));
            }
        });
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rotation(angle: f64) -> Transform {
        Transform::from_rotation_z(angle)
    }

    #[test]
    fn rotations_are_kept_once_each_up_to_the_cap() {
        let mut r = PartRotations::default();
        r.note(&Transform::IDENTITY);
        assert!(
            r.placed && r.linear.is_empty(),
            "axis-aligned: no rotation kept"
        );
        let a = rotation(0.3) * Transform::from_translation(Vec3::new(1.0, 2.0, 3.0));
        r.note(&a);
        r.note(&(Transform::from_translation(Vec3::X) * rotation(0.3)));
        assert_eq!(r.linear.len(), 1, "the same rotation at two places is one");
        assert_eq!(r.find(&a), Some(0));
        assert_eq!(r.linear[0].translation, Vec3::ZERO);
        for i in 0..2 * MAX_PART_ROTATIONS {
            r.note(&rotation(0.01 * (i + 1) as f64 + 1.0));
        }
        assert!(r.overflow);
        assert_eq!(r.linear.len(), MAX_PART_ROTATIONS);
        // Negative control: a rotation never noted has no box of its own.
        assert_eq!(r.find(&rotation(2.9)), None);
    }

    #[test]
    fn rotated_boxes_match_rotating_the_samples() {
        let samples = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(10.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(3.0, 4.0, 5.0),
        ];
        let mut r = PartRotations::default();
        let t = rotation(0.7);
        r.note(&t);
        let mut e = PartExtent::new(1);
        let b = BoundingBox::from_points(samples);
        e.add(&b, &samples[..2], &r);
        e = e.merge({
            let mut other = PartExtent::new(1);
            other.add(&b, &samples[2..], &r);
            other
        });
        let direct = BoundingBox::from_points(samples.iter().map(|&p| t.transform_point3(p)));
        assert_eq!(e.rotated[0], direct);
        assert!(e.samples.is_empty(), "no samples kept under the cap");
    }
}
