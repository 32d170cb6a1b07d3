//! Ray intersection with any parametric surface (tori, B-splines, revolutions, extrusions,
//! offsets): a tree of (u, v) cells whose boxes hold the surface over them, built once per
//! face, and Newton's method on `S(u, v) = o + t·d` from the centre of each leaf a ray
//! enters. The boxes are the sampled points inflated by a bound of the surface's deviation
//! between samples (second derivatives), so a hit is not missed because its cell's box was
//! too tight; the leaves are small enough that the surface is nearly flat over each, so
//! Newton converges from the centre to the hit in it for every ray that does not graze it.

use std::cell::Cell;
use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::sync::atomic::{AtomicUsize, Ordering as AtomicOrdering};
use std::sync::{Arc, OnceLock};

use cadre_geom::Surface;
use glam::DVec3;

/// Largest depth of the tree (each level halves a cell in one direction).
const MAX_DEPTH: u32 = 28;
/// A leaf's sampled normals stay within this cosine of its centre's (about 18°).
const FLAT_COS: f64 = 0.95;
/// Knot spans or angular pieces a direction is split into at the root, at most.
const MAX_ROOT_SPLITS: usize = 64;
/// The largest angle, in radians, a root cell spans in a periodic direction.
const MAX_ANGLE: f64 = std::f64::consts::FRAC_PI_2;
/// Newton iterations per leaf.
const NEWTON_STEPS: usize = 24;
/// How far Newton's iterates may roam from their cell, in cell sizes each way, before a
/// step is damped.
const ROAM: f64 = 8.0;
/// Halvings of a Newton step, at most, that leaves its cell before the step is refused.
const DAMPING_HALVINGS: u32 = 12;
/// Halvings of a leaf, at most, while isolating the nearest hit of a grazing ray.
const REFINE_DEPTH: u32 = 12;
/// Halvings of a leaf, at most, where Newton's method found no hit for a grazing ray.
const MISSED_REFINE_DEPTH: u32 = 4;
/// A ray meeting a cell's centre at less than this sine of an angle (about 17°) may have
/// thrown Newton's method off a hit there.
const GRAZING_SIN: f64 = 0.0;
/// Cell halvings per ray, at most (each samples two cells): bounds the work of a ray
/// running along a surface inside many cells' boxes.
const REFINE_BUDGET: u32 = 128;
/// Refined cells a [`RefineCache`] keeps, at most, by default (about 170 bytes each).
pub(crate) const REFINE_CACHE_CELLS: usize = 1 << 19;
/// Safety factor on the sampled second-derivative bound.
const CURVATURE_SAFETY: f64 = 2.0;

/// One cell of the tree.
#[derive(Clone, Copy, Debug)]
struct Node {
    /// Box holding the surface over the cell.
    lo: DVec3,
    hi: DVec3,
    /// The cell: `[u0, u1] × [v0, v1]`.
    cell: [f64; 4],
    /// Index of the first of two children, or `u32::MAX` for a leaf.
    children: u32,
    /// Sine of the largest angle between the cell's sampled normals, doubled (1 where a
    /// normal vanishes): rays steeper than this cannot meet the cell twice.
    spread: f64,
    /// A second bound, a slab across the cell's centre normal (zero where there is none):
    /// `normal · p` lies in `[range.0, range.1]` for every point of the surface over the
    /// cell. Much tighter than the box for a nearly flat cell lying oblique to the axes, so
    /// a ray grazing such a cell is not sent into it unless it passes within its thickness.
    normal: DVec3,
    range: (f64, f64),
    /// `max |Su| · Δu` and `max |Sv| · Δv`: the cell's extent on the surface each way,
    /// which chooses the direction it is halved in.
    extent_u: f64,
    extent_v: f64,
}

impl Node {
    /// Where the ray `o + t·d` (`inv` = 1 / d) enters the cell's bounds (the box and the
    /// slab), when it meets them for some `0 ≤ t ≤ t_max`.
    fn entry(&self, o: DVec3, d: DVec3, inv: DVec3, t_max: f64) -> Option<f64> {
        let (near, far) = slab_span(self.lo, self.hi, o, inv, t_max)?;
        if self.normal == DVec3::ZERO {
            return Some(near);
        }
        let (a, b) = (self.normal.dot(o), self.normal.dot(d));
        let (lo, hi) = self.range;
        if b.abs() < 1e-300 {
            return (a >= lo && a <= hi).then_some(near);
        }
        let (t1, t2) = ((lo - a) / b, (hi - a) / b);
        let near = near.max(t1.min(t2));
        let far = far.min(t1.max(t2));
        (near <= far).then_some(near)
    }

    /// The cell halved across its longer side on the surface.
    fn halves(&self) -> [[f64; 4]; 2] {
        let [u0, u1, v0, v1] = self.cell;
        if self.extent_u >= self.extent_v {
            let um = 0.5 * (u0 + u1);
            [[u0, um, v0, v1], [um, u1, v0, v1]]
        } else {
            let vm = 0.5 * (v0 + v1);
            [[u0, u1, v0, vm], [u0, u1, vm, v1]]
        }
    }
}

/// The two halves of a refined cell, once some ray has needed them (`None`: the surface is
/// not finite over that half).
type Halves = OnceLock<Box<[Option<Refined>; 2]>>;

/// A cell below a leaf, made while refining a grazing ray's hit and kept for the next ray.
struct Refined {
    node: Node,
    halves: Halves,
}

/// How many more refined cells the trees sharing it may keep: the cells a grazing ray
/// needs are the same for its neighbours (and the eight boundary probes of each pixel), so
/// they are sampled once and kept, up to this bound on memory; past it each ray samples its
/// own again.
#[derive(Clone, Debug)]
pub(crate) struct RefineCache(Arc<AtomicUsize>);

impl RefineCache {
    /// A cache keeping at most `cells` refined cells.
    pub fn new(cells: usize) -> RefineCache {
        RefineCache(Arc::new(AtomicUsize::new(cells)))
    }

    /// Takes room for two cells; false when there is none left.
    fn reserve(&self) -> bool {
        self.0
            .fetch_update(AtomicOrdering::Relaxed, AtomicOrdering::Relaxed, |left| {
                left.checked_sub(2)
            })
            .is_ok()
    }
}

/// The cell tree of one surface patch.
pub(crate) struct PatchTree {
    nodes: Vec<Node>,
    /// Per node, its refined halves (used for leaves only).
    halves: Vec<Halves>,
    cache: RefineCache,
    roots: Vec<u32>,
    /// Distance below which `S(u, v) − (o + t·d)` counts as zero.
    tolerance: f64,
}

/// A cell the ray enters at `t`, ordered nearest first in a [`BinaryHeap`].
struct Entry {
    t: f64,
    node: u32,
}

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Entry {}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        // Reversed: the heap pops the nearest.
        other.t.total_cmp(&self.t)
    }
}

/// A ray's hit: its parameter and the surface parameters there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PatchHit {
    pub t: f64,
    pub u: f64,
    pub v: f64,
}

impl PatchTree {
    /// The tree of `surface` over `[u0, u1] × [v0, v1]` (clipped to the domain where a
    /// direction is not periodic); `None` when the patch is empty or not finite.
    pub fn build(
        surface: &Surface,
        (u0, u1): (f64, f64),
        (v0, v1): (f64, f64),
        cache: RefineCache,
    ) -> Option<Self> {
        let ((du0, du1), (dv0, dv1)) = surface.domain();
        let clip = |a: f64, b: f64, lo: f64, hi: f64, periodic: bool| {
            if periodic {
                (a, b)
            } else {
                (a.max(lo), b.min(hi))
            }
        };
        let (u0, u1) = clip(u0, u1, du0, du1, surface.u_period().is_some());
        let (v0, v1) = clip(v0, v1, dv0, dv1, surface.v_period().is_some());
        if !(u0 < u1 && v0 < v1 && [u0, u1, v0, v1].iter().all(|x| x.is_finite())) {
            return None;
        }
        let us = root_splits(
            u0,
            u1,
            surface.u_breaks_within(u0, u1),
            surface.u_period().is_some(),
        );
        let vs = root_splits(
            v0,
            v1,
            surface.v_breaks_within(v0, v1),
            surface.v_period().is_some(),
        );
        let mut tree = PatchTree {
            nodes: Vec::new(),
            halves: Vec::new(),
            cache,
            roots: Vec::new(),
            tolerance: 0.0,
        };
        let mut extent = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for u in us.windows(2) {
            for v in vs.windows(2) {
                let root = tree.grow(surface, [u[0], u[1], v[0], v[1]], 0)?;
                extent = (extent.0.min(root.lo), extent.1.max(root.hi));
                tree.roots.push(tree.nodes.len() as u32);
                tree.nodes.push(root);
            }
        }
        tree.halves = (0..tree.nodes.len()).map(|_| OnceLock::new()).collect();
        tree.tolerance = 1e-10 * (extent.1 - extent.0).length().max(1e-300);
        Some(tree)
    }

    /// The box holding the whole patch.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.roots
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &r| {
                let n = &self.nodes[r as usize];
                (lo.min(n.lo), hi.max(n.hi))
            })
    }

    /// The node of `cell`, its descendants added to the tree (`None` if the surface is not
    /// finite there).
    fn grow(&mut self, surface: &Surface, cell: [f64; 4], depth: u32) -> Option<Node> {
        let (mut node, flat) = CellSample::of(surface, cell)?;
        if flat || depth >= MAX_DEPTH {
            return Some(node);
        }
        // Children are stored next to each other: reserve both slots first.
        let first = self.nodes.len();
        self.nodes.push(node);
        self.nodes.push(node);
        for (k, half) in node.halves().into_iter().enumerate() {
            self.nodes[first + k] = self.grow(surface, half, depth + 1)?;
        }
        node.children = first as u32;
        Some(node)
    }

    /// Every hit of the ray `o + t·d` with `0 < t < t_max` that `keep` accepts (given the
    /// hit's (u, v)), nearest first is not guaranteed: the nearest kept one is returned.
    pub fn nearest(
        &self,
        surface: &Surface,
        (o, d): (DVec3, DVec3),
        mut t_max: f64,
        keep: impl Fn(f64, f64) -> bool,
    ) -> Option<PatchHit> {
        let inv = d.recip();
        let mut best = None;
        let budget = Cell::new(REFINE_BUDGET);
        // Front to back: once a hit is kept, every cell entered beyond it is skipped.
        let mut queue: BinaryHeap<Entry> = self
            .roots
            .iter()
            .filter_map(|&k| {
                let n = &self.nodes[k as usize];
                n.entry(o, d, inv, t_max).map(|t| Entry { t, node: k })
            })
            .collect();
        while let Some(Entry { t: enter, node: k }) = queue.pop() {
            if enter >= t_max {
                break;
            }
            let node = &self.nodes[k as usize];
            if node.children != u32::MAX {
                for child in [node.children, node.children + 1] {
                    let n = &self.nodes[child as usize];
                    if let Some(t) = n.entry(o, d, inv, t_max) {
                        queue.push(Entry { t, node: child });
                    }
                }
                continue;
            }
            let leaf = (node, &self.halves[k as usize]);
            if let Some(hit) = self.solve(surface, (o, d), leaf, t_max, &keep, (0, &budget)) {
                t_max = hit.t;
                best = Some(hit);
            }
        }
        best
    }

    /// The nearest kept hit in `(0, t_max)` within `node`'s cell: Newton's method from its
    /// centre, trusted when the ray meets the surface more steeply than the cell's normals
    /// spread, so that it cannot hold a second, nearer hit; otherwise, and when Newton fails
    /// where the ray is that shallow, the cell is halved (the halves kept in `halves` for
    /// later rays while the cache has room) and each half the ray enters solved in turn,
    /// nearest first, down to [`REFINE_DEPTH`] more levels (a ray grazing the surface: near a
    /// silhouette), or [`MISSED_REFINE_DEPTH`] where Newton found nothing, within the ray's
    /// `budget`.
    fn solve(
        &self,
        surface: &Surface,
        (o, d): (DVec3, DVec3),
        (node, halves): (&Node, &Halves),
        t_max: f64,
        keep: &impl Fn(f64, f64) -> bool,
        (extra, budget): (u32, &Cell<u32>),
    ) -> Option<PatchHit> {
        let (cell, spread) = (node.cell, node.spread);
        let hit = self.newton(surface, (o, d), cell);
        let kept = |h: PatchHit| (h.t > 0.0 && h.t < t_max && keep(h.u, h.v)).then_some(h);
        let out_of_budget = budget.get() == 0;
        match hit {
            Some(h) => {
                let normal = surface.normal(h.u, h.v).unwrap_or(DVec3::ZERO);
                let steep = normal.dot(d).abs() > spread * d.length();
                if steep || extra >= REFINE_DEPTH || out_of_budget {
                    return kept(h);
                }
            }
            None => {
                // Newton fails in a nearly flat cell the ray crosses steeply only when the
                // ray misses the surface there; a grazing ray may have been thrown off.
                let [u0, u1, v0, v1] = cell;
                let centre = surface.normal(0.5 * (u0 + u1), 0.5 * (v0 + v1));
                let grazing =
                    centre.is_none_or(|n| n.dot(d).abs() <= spread.max(GRAZING_SIN) * d.length());
                if !grazing || extra >= MISSED_REFINE_DEPTH || out_of_budget {
                    return None;
                }
            }
        }
        budget.set(budget.get().saturating_sub(1));
        let sample = || {
            Box::new(node.halves().map(|cell| {
                CellSample::of(surface, cell).map(|(node, _)| Refined {
                    node,
                    halves: OnceLock::new(),
                })
            }))
        };
        let owned;
        let children: &[Option<Refined>; 2] = match halves.get() {
            Some(kept) => kept,
            None if self.cache.reserve() => halves.get_or_init(sample),
            None => {
                owned = sample();
                &owned
            }
        };
        let inv = d.recip();
        let mut entered: Vec<(f64, &Refined)> = children
            .iter()
            .flatten()
            .filter_map(|half| half.node.entry(o, d, inv, t_max).map(|t| (t, half)))
            .collect();
        entered.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut best: Option<PatchHit> = None;
        for (enter, half) in entered {
            let limit = best.map_or(t_max, |b| b.t);
            if enter >= limit {
                break;
            }
            let cell = (&half.node, &half.halves);
            if let Some(h) = self.solve(surface, (o, d), cell, limit, keep, (extra + 1, budget)) {
                best = Some(h);
            }
        }
        best
    }

    /// Newton's method on `S(u, v) − o − t·d = 0` from the centre of `cell`; the hit when it
    /// converges within the cell (widened by a tenth, so a hit on a cell's edge is found).
    fn newton(
        &self,
        surface: &Surface,
        (o, d): (DVec3, DVec3),
        cell: [f64; 4],
    ) -> Option<PatchHit> {
        let [u0, u1, v0, v1] = cell;
        let (mu, mv) = (0.1 * (u1 - u0), 0.1 * (v1 - v0));
        let (lo_u, hi_u, lo_v, hi_v) = (u0 - mu, u1 + mu, v0 - mv, v1 + mv);
        let (mut u, mut v) = (0.5 * (u0 + u1), 0.5 * (v0 + v1));
        let dd = d.length_squared();
        let mut t = (surface.eval(u, v) - o).dot(d) / dd;
        for _ in 0..NEWTON_STEPS {
            let s = surface.derivs(u, v);
            let f = s.point - o - d * t;
            if f.length() <= self.tolerance {
                return (u >= lo_u && u <= hi_u && v >= lo_v && v <= hi_v).then_some(PatchHit {
                    t,
                    u,
                    v,
                });
            }
            // Solve [Su Sv −d] (Δu, Δv, Δt) = −f by Cramer's rule.
            let (a, b, c) = (s.du, s.dv, -d);
            let det = a.dot(b.cross(c));
            if det.abs() < 1e-300 || !det.is_finite() {
                return None;
            }
            let r = -f;
            let step = (
                r.dot(b.cross(c)) / det,
                a.dot(r.cross(c)) / det,
                a.dot(b.cross(r)) / det,
            );
            let (wu, wv) = (ROAM * (u1 - u0), ROAM * (v1 - v0));
            let inside = |(u, v, t): (f64, f64, f64)| {
                u > u0 - wu && u < u1 + wu && v > v0 - wv && v < v1 + wv && t.is_finite()
            };
            let full = (u + step.0, v + step.1, t + step.2);
            if inside(full) {
                (u, v, t) = full;
                continue;
            }
            // The full step leaves the widened cell by more than its size. A ray nearly
            // along a direction the surface is straight in (a ruled face seen along its
            // rulings: the Jacobian nearly singular) is thrown far off by the first steps
            // from the centre though its hit lies in the cell (bug29478's face from the
            // front): the step is halved until it stays in and brings the point nearer
            // the ray. None that does: the hit, if any, is another cell's.
            let residual = f.length();
            let damped = (1..=DAMPING_HALVINGS).find_map(|k| {
                let lambda = 0.5f64.powi(k as i32);
                let p = (
                    u + lambda * step.0,
                    v + lambda * step.1,
                    t + lambda * step.2,
                );
                (inside(p) && (surface.eval(p.0, p.1) - o - d * p.2).length() < residual)
                    .then_some(p)
            });
            (u, v, t) = damped?;
        }
        None
    }
}

/// A cell's 3 × 3 samples, digested into its [`Node`] (a leaf) and whether it is flat
/// enough to stay one.
struct CellSample;

impl CellSample {
    /// Samples `cell`; `None` if the surface is not finite there.
    fn of(surface: &Surface, cell: [f64; 4]) -> Option<(Node, bool)> {
        let [u0, u1, v0, v1] = cell;
        let (hu, hv) = (0.5 * (u1 - u0), 0.5 * (v1 - v0));
        let mut lo = DVec3::INFINITY;
        let mut hi = DVec3::NEG_INFINITY;
        let (mut muu, mut muv, mut mvv) = (0.0f64, 0.0f64, 0.0f64);
        let (mut su, mut sv) = (0.0f64, 0.0f64);
        let mut normals = [DVec3::ZERO; 9];
        let mut points = [DVec3::ZERO; 9];
        for i in 0..3 {
            for j in 0..3 {
                let d = surface.derivs(u0 + hu * i as f64, v0 + hv * j as f64);
                if !d.point.is_finite() {
                    return None;
                }
                points[i * 3 + j] = d.point;
                lo = lo.min(d.point);
                hi = hi.max(d.point);
                muu = muu.max(d.duu.length());
                muv = muv.max(d.duv.length());
                mvv = mvv.max(d.dvv.length());
                su = su.max(d.du.length());
                sv = sv.max(d.dv.length());
                // Where the partials are parallel (a collapsed edge, a pole) the normal of a
                // point a step inside, so such a cell can still count as flat.
                normals[i * 3 + j] = match d.du.cross(d.dv).try_normalize() {
                    Some(n) => n,
                    None => surface
                        .normal(u0 + hu * i as f64, v0 + hv * j as f64)
                        .unwrap_or(DVec3::ZERO),
                };
            }
        }
        // The surface's distance from the bilinear pieces through the 3 × 3 samples, which
        // the box (and any slab) of the samples holds.
        let bend = CURVATURE_SAFETY * (muu * hu * hu + 2.0 * muv * hu * hv + mvv * hv * hv) / 8.0;
        let margin = bend.max(1e-12 * (hi - lo).length());
        let centre = normals[4];
        let flat = centre != DVec3::ZERO
            && normals
                .iter()
                .all(|n| *n != DVec3::ZERO && n.dot(centre) >= FLAT_COS);
        let spread = if normals.contains(&DVec3::ZERO) {
            1.0
        } else {
            let sin = normals
                .iter()
                .map(|n| n.cross(centre).length())
                .fold(0.0, f64::max);
            (2.0 * sin).min(1.0)
        };
        let range = points
            .iter()
            .map(|p| centre.dot(*p))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            });
        let node = Node {
            lo: lo - DVec3::splat(margin),
            hi: hi + DVec3::splat(margin),
            cell,
            children: u32::MAX,
            spread,
            normal: centre,
            range: (range.0 - margin, range.1 + margin),
            extent_u: su * (u1 - u0),
            extent_v: sv * (v1 - v0),
        };
        Some((node, flat))
    }
}

/// The root cells' edges in one direction: the ends, the breaks among them (at most
/// [`MAX_ROOT_SPLITS`] pieces, evenly chosen), and in a periodic direction enough even
/// splits that no piece spans more than [`MAX_ANGLE`].
fn root_splits(a: f64, b: f64, breaks: Vec<f64>, periodic: bool) -> Vec<f64> {
    let mut cuts = breaks;
    if cuts.len() + 1 > MAX_ROOT_SPLITS {
        let step = cuts.len() as f64 / MAX_ROOT_SPLITS as f64;
        cuts = (0..MAX_ROOT_SPLITS - 1)
            .map(|k| cuts[((k as f64 + 1.0) * step) as usize - 1])
            .collect();
    }
    let mut out = vec![a];
    out.extend(cuts.into_iter().filter(|&x| x > a && x < b));
    out.push(b);
    if periodic {
        let mut even = Vec::with_capacity(out.len());
        for w in out.windows(2) {
            let pieces = ((w[1] - w[0]) / MAX_ANGLE).ceil().max(1.0) as usize;
            for k in 0..pieces {
                even.push(w[0] + (w[1] - w[0]) * k as f64 / pieces as f64);
            }
        }
        even.push(b);
        out = even;
    }
    out.dedup();
    out
}

/// Where the ray `o + t·d` (`inv` = 1 / d) enters the box, when it meets it for some
/// `0 ≤ t ≤ t_max`.
pub(crate) fn slab(lo: DVec3, hi: DVec3, o: DVec3, inv: DVec3, t_max: f64) -> Option<f64> {
    slab_span(lo, hi, o, inv, t_max).map(|(near, _)| near)
}

/// Where the ray `o + t·d` (`inv` = 1 / d) enters and leaves the box, clipped to
/// `[0, t_max]`, when it meets it there.
fn slab_span(lo: DVec3, hi: DVec3, o: DVec3, inv: DVec3, t_max: f64) -> Option<(f64, f64)> {
    let a = (lo - o) * inv;
    let b = (hi - o) * inv;
    // NaN (0 · ∞, a ray in a face's plane) makes min/max take the other operand.
    let near = a.min(b).max_element().max(0.0);
    let far = a.max(b).min_element().min(t_max);
    (near <= far).then_some((near, far))
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_geom::Frame;

    fn torus() -> Surface {
        Surface::Torus {
            frame: Frame::WORLD,
            major_radius: 3.0,
            minor_radius: 1.0,
        }
    }

    #[test]
    fn rays_hit_a_torus_where_its_quartic_vanishes() {
        let surface = torus();
        let tau = std::f64::consts::TAU;
        let tree = PatchTree::build(&surface, (0.0, tau), (0.0, tau), RefineCache::new(1 << 12))
            .expect("tree");
        // Along x at height 0: the tube's outer wall at x = −4 first.
        let hit = tree
            .nearest(
                &surface,
                (DVec3::new(-10.0, 0.0, 0.0), DVec3::X),
                1e9,
                |_, _| true,
            )
            .expect("hit");
        assert!((hit.t - 6.0).abs() < 1e-9, "{hit:?}");
        // From the hole's centre upwards: nothing. Through the tube's top at x = 3: z = 1.
        assert!(
            tree.nearest(&surface, (DVec3::ZERO, DVec3::Z), 1e9, |_, _| true)
                .is_none()
        );
        let hit = tree
            .nearest(
                &surface,
                (DVec3::new(3.0, 0.0, 10.0), -DVec3::Z),
                1e9,
                |_, _| true,
            )
            .expect("hit");
        assert!((hit.t - 9.0).abs() < 1e-9, "{hit:?}");
        // Oblique rays: every hit lies on the implicit torus, and agrees with a fine march.
        let implicit = |p: DVec3| {
            let q = p.length_squared() + 9.0 - 1.0;
            q * q - 36.0 * (p.x * p.x + p.y * p.y)
        };
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..200 {
            let o = DVec3::new(next() * 12.0 - 6.0, next() * 12.0 - 6.0, 6.0);
            let target = DVec3::new(next() * 8.0 - 4.0, next() * 8.0 - 4.0, next() * 2.0 - 1.0);
            let d = (target - o).normalize();
            let found = tree.nearest(&surface, (o, d), 1e9, |_, _| true);
            // The march: first sign change of the implicit form in steps of 1e-3.
            let mut marched = None;
            let mut prev = implicit(o);
            for k in 1..20_000 {
                let t = k as f64 * 1e-3;
                let f = implicit(o + d * t);
                if f.signum() != prev.signum() {
                    marched = Some(t);
                    break;
                }
                prev = f;
            }
            match (found, marched) {
                (Some(h), Some(t)) => {
                    assert!(implicit(o + d * h.t).abs() < 1e-6, "{h:?}");
                    assert!((h.t - t).abs() < 2e-3, "{h:?} vs march {t}");
                }
                (None, None) => {}
                // A graze the march steps over, or one it catches that Newton finds at
                // the same place: only allowed when the two are tangent there.
                (f, m) => panic!("tree {f:?}, march {m:?} from {o} towards {target}"),
            }
        }
    }

    #[test]
    fn a_filter_rejecting_the_nearest_hit_gives_the_next() {
        let surface = torus();
        let tau = std::f64::consts::TAU;
        let tree = PatchTree::build(&surface, (0.0, tau), (0.0, tau), RefineCache::new(1 << 12))
            .expect("tree");
        let ray = (DVec3::new(-10.0, 0.0, 0.0), DVec3::X);
        // Keep only the tube's inner half (|v| > π/2): the ray's second hit, x = −2.
        let inner = |_: f64, v: f64| {
            let v = v.rem_euclid(tau);
            v > 0.5 * std::f64::consts::PI && v < 1.5 * std::f64::consts::PI
        };
        let hit = tree.nearest(&surface, ray, 1e9, inner).expect("hit");
        assert!((hit.t - 8.0).abs() < 1e-9, "{hit:?}");
        // Negative control: a filter keeping nothing finds nothing.
        assert!(tree.nearest(&surface, ray, 1e9, |_, _| false).is_none());
    }

    #[test]
    fn a_grazing_ray_gets_the_nearer_of_two_close_hits() {
        let surface = torus();
        let tau = std::f64::consts::TAU;
        let tree = PatchTree::build(&surface, (0.0, tau), (0.0, tau), RefineCache::new(1 << 12))
            .expect("tree");
        // Just under the tube's top (z = 1) along y: the ray meets the tube where
        // (ρ − 3)² = 1 − z², at ρ = 3 ± √(1 − z²): the outer wall first, the inner one a
        // hair farther, both in one nearly flat cell.
        let mut rays = 0;
        for z in [0.99, 0.999, 0.9999, 0.99999] {
            let gap = (1.0f64 - z * z).sqrt();
            for k in 0..41 {
                let x = -2.0 + 0.1 * f64::from(k);
                let y = ((3.0 + gap) * (3.0 + gap) - x * x).sqrt();
                let hit = tree
                    .nearest(
                        &surface,
                        (DVec3::new(x, -20.0, z), DVec3::Y),
                        1e9,
                        |_, _| true,
                    )
                    .expect("hit");
                let expected = 20.0 - y;
                // The inner wall is ≥ 2·gap·3/y farther; along a grazing ray t is
                // ill-conditioned.
                assert!(
                    (hit.t - expected).abs() < 1e-2 * gap,
                    "x {x} z {z}: {hit:?} vs {expected}"
                );
                rays += 1;
            }
        }
        assert_eq!(rays, 164);
        // The tube's inner half alone (a face ending on the top circle): the inner wall,
        // whose hit sits at the face's edge for these rays, is still found.
        let half_pi = std::f64::consts::FRAC_PI_2;
        let inner = PatchTree::build(
            &surface,
            (0.0, tau),
            (half_pi, 3.0 * half_pi),
            RefineCache::new(0),
        )
        .expect("tree");
        for z in [0.99, 0.999, 0.9999, 0.99999] {
            let gap = (1.0f64 - z * z).sqrt();
            for k in 0..21 {
                let x = -1.0 + 0.1 * f64::from(k);
                let y = ((3.0 - gap) * (3.0 - gap) - x * x).sqrt();
                let hit = inner
                    .nearest(
                        &surface,
                        (DVec3::new(x, -20.0, z), DVec3::Y),
                        1e9,
                        |_, _| true,
                    )
                    .expect("hit");
                assert!(
                    (hit.t - (20.0 - y)).abs() < 1e-2 * gap,
                    "inner, x {x} z {z}: {hit:?} vs {}",
                    20.0 - y
                );
            }
        }
    }

    /// Rays nearly along a surface's straight direction (a cylinder's rulings: the Newton
    /// Jacobian [S_u S_v −d] nearly singular) still find their hits, at the right place;
    /// rays that miss the half cylinder still miss (bug29478: a ruled face seen from the
    /// front was mostly missed).
    #[test]
    fn rays_along_the_rulings_hit_where_they_should() {
        let surface = Surface::Cylinder {
            frame: Frame::WORLD,
            radius: 1.0,
        };
        let pi = std::f64::consts::PI;
        let tree = PatchTree::build(&surface, (0.0, pi), (0.0, 10.0), RefineCache::new(1 << 12))
            .expect("tree");
        let (mut found, mut rays) = (0, 0);
        for slope in [0.02, 0.005, 0.001] {
            for k in 0..24 {
                let u = 0.2 + 2.7 * f64::from(k) / 23.0;
                let z = 1.0 + 8.0 * f64::from((k * 7) % 23) / 22.0;
                let hit_point = DVec3::new(u.cos(), u.sin(), z);
                // Leaving the tube outwards, a little off its normal, from 50 units below.
                let a = u + 0.3;
                let d = (DVec3::Z + slope * DVec3::new(a.cos(), a.sin(), 0.0)).normalize();
                let length = 50.0;
                let o = hit_point - d * length;
                assert!(
                    o.x * o.x + o.y * o.y < 1.0,
                    "the ray starts inside the tube"
                );
                rays += 1;
                if let Some(h) = tree.nearest(&surface, (o, d), 1e9, |_, _| true) {
                    assert!((h.t - length).abs() < 1e-6, "slope {slope}, u {u}: {h:?}");
                    found += 1;
                }
            }
        }
        assert_eq!(found, rays, "hits found");
        // Negative control: the same rays turned to leave through the other half (y < 0),
        // which the face does not have, miss.
        for k in 0..24 {
            let u = -0.2 - 2.7 * f64::from(k) / 23.0;
            let d = (DVec3::Z + 0.005 * DVec3::new(u.cos(), u.sin(), 0.0)).normalize();
            let o = DVec3::new(u.cos(), u.sin(), 5.0) - d * 50.0;
            assert!(
                tree.nearest(&surface, (o, d), 1e9, |_, _| true).is_none(),
                "u {u}"
            );
        }
    }

    #[test]
    fn root_splits_keep_breaks_and_bound_angles() {
        assert_eq!(root_splits(0.0, 1.0, vec![0.5], false), vec![0.0, 0.5, 1.0]);
        let s = root_splits(0.0, std::f64::consts::TAU, vec![], true);
        assert_eq!(s.len(), 5);
        let many: Vec<f64> = (1..1000).map(|k| k as f64 / 1000.0).collect();
        assert_eq!(
            root_splits(0.0, 1.0, many, false).len(),
            MAX_ROOT_SPLITS + 1
        );
    }
}
