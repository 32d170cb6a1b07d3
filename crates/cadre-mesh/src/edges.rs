//! Edge discretisation: every edge of the model sampled once, in 3D, to the linear and
//! angular deflection (like OCCT's `GCPnts_TangentialDeflection`). Every face using an edge
//! builds its trim polygon from these samples, which is what makes meshes watertight.

use cadre_brep::trim::{EdgeSample, EdgeSamples, TrimKey};
use cadre_brep::{EdgeId, Model};
use cadre_geom::{Accuracy, Curve3, Vec3};
use rayon::prelude::*;

use crate::MeshParams;

/// Deepest bisection of one curve span (2^18 pieces).
const MAX_DEPTH: u32 = 18;
/// Spans shorter than this fraction of the deflection are not split for their turning.
const MIN_TURN_SPAN: f64 = 0.1;
/// Most samples one edge may get, so a pathological curve cannot exhaust memory.
const MAX_EDGE_SAMPLES: usize = 100_000;

/// The samples of every edge of a model, indexed by edge id.
#[derive(Clone, Debug, Default)]
pub struct EdgeDiscretisation {
    samples: Vec<Vec<EdgeSample>>,
}

impl EdgeSamples for EdgeDiscretisation {
    fn samples(&self, edge: EdgeId) -> &[EdgeSample] {
        self.samples.get(edge.index()).map_or(&[], Vec::as_slice)
    }
}

impl EdgeDiscretisation {
    /// Samples every edge of `model` (in parallel). The two vertices of an edge shorter
    /// than a tenth of the deflection become one point of the mesh (see
    /// `weld_micro_edges`).
    pub fn new(model: &Model, params: &MeshParams, acc: Accuracy) -> Self {
        let mut samples: Vec<Vec<EdgeSample>> = (0..model.edges.len())
            .into_par_iter()
            .map(|i| discretise_edge(model, EdgeId(i as u32), params, acc))
            .collect();
        weld_micro_edges(model, &mut samples, MIN_TURN_SPAN * params.deflection);
        Self { samples }
    }

    /// Total number of samples (for reports).
    pub fn len(&self) -> usize {
        self.samples.iter().map(Vec::len).sum()
    }

    /// Whether no edge has samples.
    pub fn is_empty(&self) -> bool {
        self.samples.iter().all(Vec::is_empty)
    }
}

/// Gives the vertices joined by an edge no longer than `gap` (its samples just its two
/// vertices) one weld key and one position, the lowest vertex's: such an edge is a point at
/// the mesh's scale, and files have them by the dozen where faces meet in a corner, a few
/// micrometres long and with both ends clamped onto one (u, v) of a face
/// (trj7_b1-ec-214.stp: vertices 7 um apart where four faces meet):
/// meshed as edges they made slivers the faces' triangulations could not agree on.
fn weld_micro_edges(model: &Model, samples: &mut [Vec<EdgeSample>], gap: f64) {
    let n = model.vertices.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn root(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            let up = parent[parent[v as usize] as usize];
            parent[v as usize] = up;
            v = up;
        }
        v
    }
    let mut any = false;
    for (edge, s) in model.edges.iter().zip(samples.iter()) {
        let (a, b) = (edge.start.index(), edge.end.index());
        if a == b || a >= n || b >= n || s.len() != 2 || (s[0].xyz - s[1].xyz).length() > gap {
            continue;
        }
        let (ra, rb) = (root(&mut parent, a as u32), root(&mut parent, b as u32));
        if ra != rb {
            parent[ra.max(rb) as usize] = ra.min(rb);
            any = true;
        }
    }
    if !any {
        return;
    }
    for (edge, s) in model.edges.iter().zip(samples.iter_mut()) {
        let last = s.len() - 1;
        for (i, v) in [(0, edge.start), (last, edge.end)] {
            if v.index() >= n {
                continue;
            }
            let r = root(&mut parent, v.index() as u32);
            if r as usize != v.index() {
                let rep = cadre_brep::VertexId(r);
                s[i].key = TrimKey::vertex(rep);
                s[i].xyz = model.vertices[rep.index()].point;
            }
        }
    }
}

/// Samples of one edge from its start vertex to its end vertex. The ends are the vertices'
/// own points (so edges meeting at a vertex meet exactly); a degenerate edge (no curve, or one
/// whose vertices do not lie on it) is its two vertices.
pub fn discretise_edge(
    model: &Model,
    id: EdgeId,
    params: &MeshParams,
    acc: Accuracy,
) -> Vec<EdgeSample> {
    let edge = &model.edges[id.index()];
    let start = EdgeSample {
        t: 0.0,
        xyz: model.vertices[edge.start.index()].point,
        key: TrimKey::vertex(edge.start),
    };
    let end = EdgeSample {
        t: 0.0,
        xyz: model.vertices[edge.end.index()].point,
        key: TrimKey::vertex(edge.end),
    };
    let (Some(curve_id), Some((t0, t1))) = (edge.curve, model.edge_range(id, acc)) else {
        return vec![start, end];
    };
    let curve = &model.curves[curve_id.index()];
    let mut params_along = sample_curve(curve, t0, t1, params);
    if !edge.same_sense {
        params_along.reverse();
    }
    // Samples within a tenth of the deflection of a vertex go: the chord from the one before
    // to the vertex is as good at that scale, and where the curve hooks past its vertex
    // (trj7_b1-ec-214.stp edge 603, 0.002 mm beyond it and back) such a sample falls on
    // the far side of the next edge in (u, v), the loop crosses itself there and the
    // repaired face no longer welds.
    let gap = MIN_TURN_SPAN * params.deflection;
    while params_along.len() > 2 && (params_along[1].1 - start.xyz).length() <= gap {
        params_along.remove(1);
    }
    while params_along.len() > 2
        && (params_along[params_along.len() - 2].1 - end.xyz).length() <= gap
    {
        params_along.remove(params_along.len() - 2);
    }
    // An edge closing on itself keeps two inner points whatever its size: with fewer it
    // encloses nothing, and a face it bounds alone is lost (pr1sy.stp #264, a disc of a
    // 0.02 mm circle, at the benchmark's 1.4 mm deflection).
    if edge.start == edge.end && params_along.len() < 4 {
        params_along = (0..4)
            .map(|k| {
                let t = t0 + (t1 - t0) * k as f64 / 3.0;
                (t, curve.eval(t))
            })
            .collect();
        if !edge.same_sense {
            params_along.reverse();
        }
    }
    let n = params_along.len();
    let mut out = Vec::with_capacity(n);
    for (i, &(t, p)) in params_along.iter().enumerate() {
        if i == 0 {
            out.push(EdgeSample { t, ..start });
        } else if i + 1 == n {
            out.push(EdgeSample { t, ..end });
        } else {
            out.push(EdgeSample {
                t,
                xyz: p,
                key: TrimKey::edge(id, i),
            });
        }
    }
    out
}

/// Parameters and points along `curve` over `[t0, t1]` such that each chord is within the
/// deflection of the curve and turns by at most the angle.
pub fn sample_curve(curve: &Curve3, t0: f64, t1: f64, params: &MeshParams) -> Vec<(f64, Vec3)> {
    let mut stops = vec![t0];
    if !matches!(curve, Curve3::Line { .. }) {
        stops.extend(curve.breaks_within(t0, t1));
        // Conics start from quarter turns so the tangent test sees their curvature.
        if let Some(period) = curve.period() {
            let pieces = ((t1 - t0) / (0.25 * period)).ceil().max(1.0) as usize;
            for k in 1..pieces {
                stops.push(t0 + (t1 - t0) * k as f64 / pieces as f64);
            }
        }
        stops.sort_by(f64::total_cmp);
        stops.dedup();
    }
    stops.push(t1);
    let mut out = Vec::with_capacity(stops.len() * 4);
    let d0 = curve.derivs(t0);
    out.push((t0, d0.point));
    let mut prev = (t0, d0.point, d0.d1);
    // A stop within a tenth of the deflection of the one before or of the end is left out:
    // a knot a rounding away from an end (trj4_pm2-ec-214.stp edge #21483, knots at -1.6e-7
    // and 0, its range starting at the first) made a sample 2e-7 mm from the vertex, which
    // the face's triangulation merged with it, leaving the neighbour's edge open.
    let gap = MIN_TURN_SPAN * params.deflection;
    let end_point = curve.eval(t1);
    let last = stops.len() - 1;
    for (i, &t) in stops.iter().enumerate().skip(1) {
        if t <= prev.0 {
            continue;
        }
        let d = curve.derivs(t);
        if i < last && ((d.point - prev.1).length() <= gap || (d.point - end_point).length() <= gap)
        {
            continue;
        }
        let next = (t, d.point, d.d1);
        bisect(curve, prev, next, params, 0, &mut out);
        out.push((t, d.point));
        prev = next;
    }
    out
}

/// Pushes the inner points of `[a, b]` needed for the tolerances, in order.
fn bisect(
    curve: &Curve3,
    a: (f64, Vec3, Vec3),
    b: (f64, Vec3, Vec3),
    params: &MeshParams,
    depth: u32,
    out: &mut Vec<(f64, Vec3)>,
) {
    if depth >= MAX_DEPTH || out.len() >= MAX_EDGE_SAMPLES {
        return;
    }
    let tm = 0.5 * (a.0 + b.0);
    let dm = curve.derivs(tm);
    let chord = b.1 - a.1;
    let len2 = chord.length_squared();
    let off_chord = |p: Vec3| {
        let off = p - a.1;
        if len2 > 0.0 {
            (off - chord * (off.dot(chord) / len2)).length()
        } else {
            off.length()
        }
    };
    // The quarter points too: an S-shaped span (an inflection) has its midpoint on the chord
    // and parallel end tangents, yet bulges on both sides.
    let quarter = |s: f64| curve.eval(a.0 + (b.0 - a.0) * s);
    let deviation = off_chord(dm.point)
        .max(off_chord(quarter(0.25)))
        .max(off_chord(quarter(0.75)));
    let angle = |x: Vec3, y: Vec3| match (x.try_normalize(), y.try_normalize()) {
        (Some(tx), Some(ty)) => tx.dot(ty).clamp(-1.0, 1.0).acos(),
        _ => 0.0,
    };
    // Total turning through the midpoint: an arc's end-to-end angle, and more for an S.
    let turn = angle(a.2, dm.d1) + angle(dm.d1, b.2);
    // A tiny chord cannot get better by splitting (and a zero one means a degenerate span).
    let reach = len2.sqrt().max((dm.point - a.1).length());
    let tiny = reach <= 1e-3 * params.deflection;
    // Turning is not refined below a tenth of the deflection: the span is a point at that
    // scale, and refining it anyway packs samples into a hook at a curve's end
    // (trj4_pm2-ec-214.stp edge 453 turns within 0.001 mm of its vertex; the samples there
    // landed on the next edge's pcurve and the face did not weld).
    let short = reach <= MIN_TURN_SPAN * params.deflection;
    if (deviation > params.deflection || (turn > params.angle && !short)) && !tiny {
        let m = (tm, dm.point, dm.d1);
        bisect(curve, a, m, params, depth + 1, out);
        out.push((tm, dm.point));
        bisect(curve, m, b, params, depth + 1, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_geom::curve::CurveFrame;

    #[test]
    fn s_shaped_span_is_split() {
        // Midpoint on the chord, end tangents parallel: only the quarter points see it.
        let s = cadre_geom::BSplineCurve::bezier(
            vec![
                Vec3::ZERO,
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(2.0, -1.0, 0.0),
                Vec3::new(3.0, 0.0, 0.0),
            ],
            None,
        )
        .unwrap();
        let params = MeshParams {
            deflection: 0.01,
            angle: 0.5,
            ..MeshParams::default()
        };
        let curve = Curve3::BSpline(s);
        let samples = sample_curve(&curve, 0.0, 1.0, &params);
        assert!(samples.len() > 8, "{}", samples.len());
        within_deflection(&curve, &samples, params.deflection);
    }

    #[test]
    fn circle_samples_meet_the_deflection_and_angle() {
        let circle = Curve3::Circle {
            frame: CurveFrame {
                origin: Vec3::ZERO,
                x: Vec3::X,
                y: Vec3::Y,
            },
            radius: 10.0,
        };
        let params = MeshParams {
            deflection: 0.01,
            angle: 0.5,
            ..MeshParams::default()
        };
        let s = sample_curve(&circle, 0.0, std::f64::consts::TAU, &params);
        for w in s.windows(2) {
            let dt = w[1].0 - w[0].0;
            // Sagitta of a chord spanning dt radians.
            let sagitta = 10.0 * (1.0 - (0.5 * dt).cos());
            assert!(sagitta <= 0.01 + 1e-12, "sagitta {sagitta}");
            assert!(dt <= 0.5 + 1e-12);
        }
        // And not absurdly many: the optimum is about 2π / (2 acos(1 - 0.001)) ≈ 70.
        assert!(s.len() < 200, "{}", s.len());
        let line = Curve3::Line {
            origin: Vec3::ZERO,
            direction: Vec3::X,
        };
        assert_eq!(sample_curve(&line, 0.0, 5.0, &params).len(), 2);
    }

    fn within_deflection(curve: &Curve3, samples: &[(f64, Vec3)], deflection: f64) {
        for w in samples.windows(2) {
            for k in 1..10 {
                let t = w[0].0 + (w[1].0 - w[0].0) * k as f64 / 10.0;
                let p = curve.eval(t);
                let (a, b) = (w[0].1, w[1].1);
                let d = (p - a) - (b - a) * ((p - a).dot(b - a) / (b - a).length_squared());
                assert!(d.length() <= deflection * 1.01, "{}", d.length());
            }
        }
    }

    #[test]
    fn a_knot_a_rounding_from_the_start_makes_no_sample() {
        // Knots at 0 and 1e-7: the span between them is a point.
        let s = cadre_geom::BSplineCurve::try_new(
            3,
            vec![0.0, 0.0, 0.0, 0.0, 1e-7, 1.0, 1.0, 1.0, 1.0],
            vec![
                Vec3::ZERO,
                Vec3::new(1e-7, 0.0, 0.0),
                Vec3::new(3.0, 1.0, 0.0),
                Vec3::new(6.0, 1.0, 0.0),
                Vec3::new(9.0, 0.0, 0.0),
            ],
            None,
        )
        .unwrap();
        let curve = Curve3::BSpline(s);
        let params = MeshParams {
            deflection: 0.01,
            angle: 0.2,
            ..MeshParams::default()
        };
        let samples = sample_curve(&curve, 0.0, 1.0, &params);
        let first = samples[0].1;
        for &(t, p) in &samples[1..] {
            assert!((p - first).length() > 1e-5, "sample at t = {t}, {p:?}");
        }
        within_deflection(&curve, &samples, params.deflection);
    }

    #[test]
    fn a_hook_below_the_deflection_at_the_end_is_not_refined() {
        // Straight for 10 mm, then turning back within 1e-4 mm of the end.
        let s = cadre_geom::BSplineCurve::bezier(
            vec![
                Vec3::ZERO,
                Vec3::new(5.0, 0.0, 0.0),
                Vec3::new(10.0, 0.0, 0.0),
                Vec3::new(10.0 - 1e-4, 1e-4, 0.0),
            ],
            None,
        )
        .unwrap();
        let curve = Curve3::BSpline(s);
        let params = MeshParams {
            deflection: 0.01,
            angle: 0.1,
            ..MeshParams::default()
        };
        let samples = sample_curve(&curve, 0.0, 1.0, &params);
        let end = samples[samples.len() - 1].1;
        let near_end = samples[..samples.len() - 1]
            .iter()
            .filter(|s| (s.1 - end).length() < 1e-3)
            .count();
        assert!(
            near_end <= 1,
            "{near_end} samples within 0.001 mm of the end"
        );
        within_deflection(&curve, &samples, params.deflection);
    }

    #[test]
    fn the_ends_of_an_edge_below_the_gap_weld_into_one_point() {
        use cadre_brep::{CurveId, Edge, Vertex, VertexId};
        // A 10 mm line from A to B, a 1 um line from B to C, a 10 mm line from C to D.
        let mut model = Model::default();
        let points = [
            Vec3::ZERO,
            Vec3::new(10.0, 0.0, 0.0),
            Vec3::new(10.0, 1e-3, 0.0),
            Vec3::new(10.0, 10.0, 0.0),
        ];
        for (i, p) in points.iter().enumerate() {
            model.vertices.push(Vertex {
                point: *p,
                step_id: i as u64 + 1,
            });
        }
        for (i, w) in [0u32, 1, 2, 3].windows(2).enumerate() {
            let (a, b) = (points[w[0] as usize], points[w[1] as usize]);
            model.curves.push(Curve3::Line {
                origin: a,
                direction: b - a,
            });
            model.edges.push(Edge {
                curve: Some(CurveId(i as u32)),
                start: VertexId(w[0]),
                end: VertexId(w[1]),
                same_sense: true,
                pcurves: Vec::new(),
                step_id: 10 + i as u64,
            });
        }
        let at = |deflection: f64| {
            let params = MeshParams {
                deflection,
                ..MeshParams::default()
            };
            EdgeDiscretisation::new(&model, &params, Accuracy::default())
        };
        // Deflection 0.1: the 0.001 mm edge is below its tenth; B and C are one point.
        let d = at(0.1);
        let short = d.samples(EdgeId(1));
        assert_eq!(short[0].key, short[1].key);
        assert_eq!(short[0].xyz, short[1].xyz);
        let (ab, cd) = (d.samples(EdgeId(0)), d.samples(EdgeId(2)));
        assert_eq!(ab[ab.len() - 1].key, cd[0].key);
        assert_eq!(cd[0].xyz, points[1]);
        // Deflection 0.001: the edge is ten times its tenth and keeps its two ends.
        let d = at(0.001);
        let short = d.samples(EdgeId(1));
        assert_ne!(short[0].key, short[1].key);
        assert_eq!(d.samples(EdgeId(2))[0].xyz, points[2]);
    }

    /// pr1sy.stp #264: a disc bounded by one 0.02 mm circle, meshed at a 1.4 mm deflection.
    /// The closed edge keeps two inner points; an open arc of the same size (the negative
    /// control) is its two vertices, as any edge below a tenth of the deflection.
    #[test]
    fn a_tiny_closed_edge_keeps_an_area() {
        use cadre_brep::{CurveId, Edge, Vertex, VertexId};
        let mut model = Model::default();
        let circle = Curve3::Circle {
            frame: CurveFrame {
                origin: Vec3::ZERO,
                x: Vec3::X,
                y: Vec3::Y,
            },
            radius: 0.02,
        };
        for p in [circle.eval(0.0), circle.eval(1.0)] {
            model.vertices.push(Vertex {
                point: p,
                step_id: 1,
            });
        }
        model.curves.push(circle);
        for (end, step_id) in [(0, 10), (1, 11)] {
            model.edges.push(Edge {
                curve: Some(CurveId(0)),
                start: VertexId(0),
                end: VertexId(end),
                same_sense: true,
                pcurves: Vec::new(),
                step_id,
            });
        }
        let params = MeshParams {
            deflection: 1.4,
            ..MeshParams::default()
        };
        let d = EdgeDiscretisation::new(&model, &params, Accuracy::default());
        let closed = d.samples(EdgeId(0));
        assert_eq!(closed.len(), 4);
        assert!((closed[1].xyz - closed[2].xyz).length() > 0.01);
        assert_eq!(d.samples(EdgeId(1)).len(), 2);
    }
}
