//! Cutting the trim segments into pieces that meet only at their ends, before they go into
//! the triangulation as constraints.
//!
//! Spade's splitting insertion (`add_constraint_and_split`) finds crossings while it walks
//! along the new constraint; on degenerate trims (repeated points, zero-length or
//! overlapping sides, a vertex on another side, collinear overlaps) rounding can make it
//! split the same crossing over and over, forever. Here every crossing is found up front, in
//! a few bounded passes over the pairs of segments that a uniform grid puts near each other:
//! segments are cut at the points where they cross, at the vertices lying on them, and where
//! they overlap, so the pieces can go in with spade's non-splitting insertion. A piece that
//! still conflicts (by a rounding) is left out by the caller.
//!
//! All tests use one distance tolerance, the merge tolerance of the trim points: a vertex
//! within it of a segment lies on it, a crossing within it of a vertex is that vertex.

use std::collections::{HashMap, HashSet};

use spade::Point2;

use super::domain::edge_key;

/// The points of one [`PointGrid`] cell: id and position.
type Bucket = Vec<(u32, Point2<f64>)>;

/// Points bucketed in square cells of the tolerance, to find an earlier point within the
/// tolerance of a new one (per coordinate) by looking at the 3 × 3 cells around it.
pub(crate) struct PointGrid {
    tol: f64,
    cells: HashMap<(i64, i64), Bucket>,
}

impl PointGrid {
    /// An empty grid for the distance tolerance `tol` (positive).
    pub fn new(tol: f64, capacity: usize) -> PointGrid {
        PointGrid {
            tol,
            cells: HashMap::with_capacity(capacity),
        }
    }

    /// The distance tolerance.
    pub fn tol(&self) -> f64 {
        self.tol
    }

    /// The cell of `p`. The casts saturate, which only makes far-out cells shared, never
    /// misses a neighbour.
    fn cell(&self, p: Point2<f64>) -> (i64, i64) {
        (
            (p.x / self.tol).floor() as i64,
            (p.y / self.tol).floor() as i64,
        )
    }

    /// The id of an inserted point within the tolerance of `p` in both coordinates, if any.
    pub fn find(&self, p: Point2<f64>) -> Option<u32> {
        let (cx, cy) = self.cell(p);
        for dx in -1..=1i64 {
            for dy in -1..=1i64 {
                let key = (cx.saturating_add(dx), cy.saturating_add(dy));
                for &(id, q) in self.cells.get(&key).into_iter().flatten() {
                    if (q.x - p.x).abs() <= self.tol && (q.y - p.y).abs() <= self.tol {
                        return Some(id);
                    }
                }
            }
        }
        None
    }

    /// Adds point `id` at `p`.
    pub fn insert(&mut self, p: Point2<f64>, id: u32) {
        let key = self.cell(p);
        self.cells.entry(key).or_default().push((id, p));
    }
}

/// The segments cut into pieces.
#[derive(Debug, Default)]
pub(crate) struct Arrangement {
    /// Crossing points created, in the plane; the `k`-th has id `base + k` (see [`arrange`]).
    pub crossings: Vec<Point2<f64>>,
    /// The pieces, as vertex ids: distinct (undirected), never from a vertex to itself.
    pub pieces: Vec<[u32; 2]>,
    /// Crossings not cut because the crossing budget was spent (counted in every pass that
    /// meets them).
    pub uncut: usize,
    /// Whether every pair of nearby segments was tested (false when the pair budget ran out
    /// on a pathological trim: the untested crossings stay in the pieces).
    pub complete: bool,
}

/// Cuts `segs` (vertex id pairs, distinct, each with two different vertices) where they
/// cross, touch or overlap. `pos` holds the position of every vertex id below `base`; `grid`
/// holds every vertex of the triangulation, so that a crossing at an existing vertex reuses
/// it, and receives the crossings created (at most `max_crossings`, ids from `base`).
pub(crate) fn arrange(
    pos: &[Point2<f64>],
    segs: &[[u32; 2]],
    grid: &mut PointGrid,
    base: u32,
    max_crossings: usize,
) -> Arrangement {
    let mut cutter = Cutter {
        pos,
        base,
        tol: grid.tol(),
        grid,
        max_crossings,
        crossings: Vec::new(),
        cuts: Vec::new(),
        uncut: 0,
    };
    let mut pieces = segs.to_vec();
    let mut complete = true;
    // Later passes find what the cuts made: a crossing point on a third segment that its
    // crossings with the two did not snap to, overlaps between pieces. Each pass cuts
    // less; the count bounds the work should rounding keep making new cuts.
    for _ in 0..PASSES {
        let (next, done, cut) = cutter.pass(&pieces);
        pieces = next;
        complete &= done;
        if !cut {
            break;
        }
    }
    Arrangement {
        crossings: cutter.crossings,
        pieces,
        uncut: cutter.uncut,
        complete,
    }
}

/// Most passes of [`arrange`] over the pieces.
const PASSES: usize = 3;

/// Finds the cuts of one pair of segments.
struct Cutter<'a> {
    pos: &'a [Point2<f64>],
    base: u32,
    tol: f64,
    grid: &'a mut PointGrid,
    max_crossings: usize,
    crossings: Vec<Point2<f64>>,
    /// (segment index, vertex id) of every cut.
    cuts: Vec<(u32, u32)>,
    uncut: usize,
}

impl Cutter<'_> {
    /// Cuts `segs` once: returns the pieces, whether every nearby pair was tested, and
    /// whether anything was cut.
    fn pass(&mut self, segs: &[[u32; 2]]) -> (Vec<[u32; 2]>, bool, bool) {
        let buckets = SegmentGrid::new(|id| self.point(id), segs, self.tol);
        // Far above what trims with sane sampling need (a few pairs per segment); bounds
        // the work on pathological ones, such as thousands of long segments across one
        // region.
        let budget = 64 * segs.len() + (1 << 22);
        let complete = buckets.for_each_pair(budget, |s, t| self.cut_pair(segs, s, t));
        let mut cuts = std::mem::take(&mut self.cuts);
        let cut = !cuts.is_empty();
        (pieces(segs, &mut cuts, |id| self.point(id)), complete, cut)
    }

    /// Position of vertex `id`.
    fn point(&self, id: u32) -> Point2<f64> {
        match id.checked_sub(self.base) {
            Some(k) => self.crossings[k as usize],
            None => self.pos[id as usize],
        }
    }

    /// Records where segments `s` and `t` cut each other: at an end of one lying on the
    /// other (touching, or overlapping collinear segments: both ends of the overlap), or
    /// else at their crossing point.
    fn cut_pair(&mut self, segs: &[[u32; 2]], s: usize, t: usize) {
        let ([a, b], [c, d]) = (segs[s], segs[t]);
        let [pa, pb, pc, pd] = [a, b, c, d].map(|id| self.point(id));
        let mut touch = false;
        for (v, pv) in [(c, pc), (d, pd)] {
            if v != a && v != b && on_segment(pv, pa, pb, self.tol) {
                self.cuts.push((s as u32, v));
                touch = true;
            }
        }
        for (v, pv) in [(a, pa), (b, pb)] {
            if v != c && v != d && on_segment(pv, pc, pd, self.tol) {
                self.cuts.push((t as u32, v));
                touch = true;
            }
        }
        // Segments from a common vertex meet there; they can meet again only by
        // overlapping, which the end tests above found.
        let shared = a == c || a == d || b == c || b == d;
        if touch || shared {
            return;
        }
        if let Some(x) = crossing([pa, pb], [pc, pd], self.tol) {
            self.cut_at_crossing(x, [s, t], [[a, b], [c, d]]);
        }
    }

    /// Cuts segments `st` (with ends `ends`) at their crossing point `x`: at the vertex
    /// within the tolerance of it if there is one, else at a new vertex.
    fn cut_at_crossing(&mut self, x: Point2<f64>, st: [usize; 2], ends: [[u32; 2]; 2]) {
        let v = match self.grid.find(x) {
            Some(v) => v,
            None if self.crossings.len() < self.max_crossings => {
                let v = self.base + self.crossings.len() as u32;
                self.crossings.push(x);
                self.grid.insert(x, v);
                v
            }
            None => {
                self.uncut += 1;
                return;
            }
        };
        for (s, e) in st.into_iter().zip(ends) {
            if !e.contains(&v) {
                self.cuts.push((s as u32, v));
            }
        }
    }
}

/// Twice the signed area of the triangle `a`, `b`, `p`: positive when `p` is left of the
/// line from `a` to `b`, and |b − a| times its distance from that line.
fn side(a: Point2<f64>, b: Point2<f64>, p: Point2<f64>) -> f64 {
    (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
}

/// Length of `b − a`.
fn length(a: Point2<f64>, b: Point2<f64>) -> f64 {
    (b.x - a.x).hypot(b.y - a.y)
}

/// Whether `p` lies within `tol` of the line through `a` and `b`, strictly between them.
/// The rounding of [`side`] (a few ulps of the coordinates times the length) is far below
/// the tolerance, so the answer is stable.
fn on_segment(p: Point2<f64>, a: Point2<f64>, b: Point2<f64>, tol: f64) -> bool {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let along = dx * (p.x - a.x) + dy * (p.y - a.y);
    let len2 = dx * dx + dy * dy;
    along > 0.0 && along < len2 && side(a, b, p).abs() <= tol * length(a, b)
}

/// The point where segments `s` and `t` cross, when each has its ends on opposite sides of
/// the other's line, farther than `tol` from it. Kept within both segments' bounding boxes,
/// which nearly parallel segments could otherwise miss by the rounding of the parameter.
fn crossing(s: [Point2<f64>; 2], t: [Point2<f64>; 2], tol: f64) -> Option<Point2<f64>> {
    let apart = |l: [Point2<f64>; 2], p: [Point2<f64>; 2]| {
        let lim = tol * length(l[0], l[1]);
        let (o0, o1) = (side(l[0], l[1], p[0]), side(l[0], l[1], p[1]));
        (o0 > lim && o1 < -lim) || (o0 < -lim && o1 > lim)
    };
    if !apart(s, t) || !apart(t, s) {
        return None;
    }
    let (rx, ry) = (s[1].x - s[0].x, s[1].y - s[0].y);
    let (qx, qy) = (t[1].x - t[0].x, t[1].y - t[0].y);
    let den = rx * qy - ry * qx;
    let num = (t[0].x - s[0].x) * qy - (t[0].y - s[0].y) * qx;
    let k = (num / den).clamp(0.0, 1.0);
    if !k.is_finite() {
        return None;
    }
    let clamp = |v: f64, [p, q]: [f64; 2], [r, w]: [f64; 2]| {
        v.clamp(p.min(q).max(r.min(w)), p.max(q).min(r.max(w)))
    };
    let x = clamp(s[0].x + k * rx, [s[0].x, s[1].x], [t[0].x, t[1].x]);
    let y = clamp(s[0].y + k * ry, [s[0].y, s[1].y], [t[0].y, t[1].y]);
    Some(Point2::new(x, y))
}

/// The segments cut at `cuts` (segment index, vertex id), in order along each, the
/// pieces shared by overlapping segments kept once.
fn pieces(
    segs: &[[u32; 2]],
    cuts: &mut [(u32, u32)],
    point: impl Fn(u32) -> Point2<f64>,
) -> Vec<[u32; 2]> {
    cuts.sort_unstable();
    let mut out = Vec::with_capacity(segs.len() + cuts.len());
    let mut seen = HashSet::with_capacity(segs.len() + cuts.len());
    let mut push = |p: u32, q: u32, out: &mut Vec<[u32; 2]>| {
        if p != q && seen.insert(edge_key(p, q)) {
            out.push([p, q]);
        }
    };
    let mut rest = &cuts[..];
    let mut on: Vec<(f64, u32)> = Vec::new();
    for (s, &[a, b]) in segs.iter().enumerate() {
        let n = rest.partition_point(|c| c.0 <= s as u32);
        let (here, tail) = rest.split_at(n);
        rest = tail;
        let (pa, pb) = (point(a), point(b));
        let (dx, dy) = (pb.x - pa.x, pb.y - pa.y);
        let len2 = dx * dx + dy * dy;
        // Parameter along the segment; a cut vertex that projects onto an end or beyond
        // (a crossing snapped to a vertex a tolerance away) is no cut of this segment.
        on.clear();
        on.extend(here.iter().filter_map(|&(_, v)| {
            let p = point(v);
            let k = (dx * (p.x - pa.x) + dy * (p.y - pa.y)) / len2;
            (k > 0.0 && k < 1.0).then_some((k, v))
        }));
        on.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)));
        on.dedup_by_key(|c| c.1);
        let mut from = a;
        for &(_, v) in on.iter() {
            push(from, v, &mut out);
            from = v;
        }
        push(from, b, &mut out);
    }
    out
}

/// Segment indices bucketed by the cells of a uniform grid that their (tolerance-widened)
/// bounding boxes cover, so that only segments sharing a cell are tested against each other.
struct SegmentGrid {
    /// Lower corner of the grid.
    lo: Point2<f64>,
    /// Cells per unit length.
    scale: f64,
    nx: usize,
    ny: usize,
    /// Start of each cell's list in `items` (`nx * ny + 1` entries).
    start: Vec<u32>,
    items: Vec<u32>,
    /// Widened bounding box of every segment: lower and upper corner.
    boxes: Vec<[Point2<f64>; 2]>,
}

impl SegmentGrid {
    /// Buckets `segs`, with about one cell per segment, fewer when long segments would be
    /// copied into too many cells (memory stays within a small multiple of the segments).
    fn new(pos: impl Fn(u32) -> Point2<f64>, segs: &[[u32; 2]], tol: f64) -> SegmentGrid {
        let boxes: Vec<[Point2<f64>; 2]> = segs
            .iter()
            .map(|&[a, b]| {
                let (p, q) = (pos(a), pos(b));
                [
                    Point2::new(p.x.min(q.x) - tol, p.y.min(q.y) - tol),
                    Point2::new(p.x.max(q.x) + tol, p.y.max(q.y) + tol),
                ]
            })
            .collect();
        let mut lo = Point2::new(f64::INFINITY, f64::INFINITY);
        let mut hi = Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
        for [p, q] in &boxes {
            lo = Point2::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Point2::new(hi.x.max(q.x), hi.y.max(q.y));
        }
        let mut grid = SegmentGrid {
            lo,
            scale: 0.0,
            nx: 1,
            ny: 1,
            start: Vec::new(),
            items: Vec::new(),
            boxes,
        };
        grid.choose_cells(hi, segs.len());
        grid.fill();
        grid
    }

    /// Picks the cell size: square cells, about one per segment, doubled in size until the
    /// boxes cover at most a few cells each on average. Each doubling at least halves the
    /// larger cell count, so this ends after about log2(segments) rounds.
    fn choose_cells(&mut self, hi: Point2<f64>, n: usize) {
        let (wx, wy) = (hi.x - self.lo.x, hi.y - self.lo.y);
        if !(wx.is_finite() && wy.is_finite() && wx > 0.0 && wy > 0.0) || n < 2 {
            return;
        }
        let n = n as f64;
        let mut size = (wx * wy / n).sqrt().max(wx.max(wy) / n);
        let limit = 8 * self.boxes.len() + 4096;
        loop {
            self.scale = 1.0 / size;
            self.nx = ((wx * self.scale).ceil() as usize).max(1);
            self.ny = ((wy * self.scale).ceil() as usize).max(1);
            if self.nx * self.ny == 1 || self.entries() <= limit {
                return;
            }
            size *= 2.0;
        }
    }

    /// The cell column (or row) of coordinate `x` from the grid's corner `x0`, clamped.
    fn index(&self, x: f64, x0: f64, n: usize) -> usize {
        let t = (x - x0) * self.scale;
        if t >= 0.0 { (t as usize).min(n - 1) } else { 0 }
    }

    /// Cell ranges (columns, rows) of a box, inclusive.
    fn range(&self, [p, q]: [Point2<f64>; 2]) -> [usize; 4] {
        [
            self.index(p.x, self.lo.x, self.nx),
            self.index(q.x, self.lo.x, self.nx),
            self.index(p.y, self.lo.y, self.ny),
            self.index(q.y, self.lo.y, self.ny),
        ]
    }

    /// Number of (cell, segment) entries with the current cells, saturating.
    fn entries(&self) -> usize {
        self.boxes
            .iter()
            .map(|&b| {
                let [x0, x1, y0, y1] = self.range(b);
                (x1 - x0 + 1).saturating_mul(y1 - y0 + 1)
            })
            .fold(0usize, usize::saturating_add)
    }

    /// Fills the cell lists.
    fn fill(&mut self) {
        let cells = self.nx * self.ny;
        let mut count = vec![0u32; cells + 1];
        for &b in &self.boxes {
            let [x0, x1, y0, y1] = self.range(b);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    count[y * self.nx + x + 1] += 1;
                }
            }
        }
        for c in 0..cells {
            count[c + 1] += count[c];
        }
        let mut fill = count.clone();
        let mut items = vec![0u32; count[cells] as usize];
        for (i, &b) in self.boxes.iter().enumerate() {
            let [x0, x1, y0, y1] = self.range(b);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let c = y * self.nx + x;
                    items[fill[c] as usize] = i as u32;
                    fill[c] += 1;
                }
            }
        }
        self.start = count;
        self.items = items;
    }

    /// Calls `f` once on every pair of segments whose boxes overlap, unless more than
    /// `budget` pairs sharing a cell come up; returns whether all were visited. A pair is
    /// visited in the cell holding the lower corner of the boxes' overlap only, so pairs
    /// sharing several cells are not visited twice.
    fn for_each_pair(&self, budget: usize, mut f: impl FnMut(usize, usize)) -> bool {
        let mut work = 0usize;
        for c in 0..self.nx * self.ny {
            let list = &self.items[self.start[c] as usize..self.start[c + 1] as usize];
            for (k, &s) in list.iter().enumerate() {
                work += list.len() - k - 1;
                if work > budget {
                    return false;
                }
                for &t in &list[k + 1..] {
                    if self.owns(c, s as usize, t as usize) {
                        f(s as usize, t as usize);
                    }
                }
            }
        }
        true
    }

    /// Whether the boxes of `s` and `t` overlap and cell `c` holds the overlap's lower
    /// corner.
    fn owns(&self, c: usize, s: usize, t: usize) -> bool {
        let ([p, q], [r, w]) = (self.boxes[s], self.boxes[t]);
        let lo = Point2::new(p.x.max(r.x), p.y.max(r.y));
        if lo.x > q.x.min(w.x) || lo.y > q.y.min(w.y) {
            return false;
        }
        let x = self.index(lo.x, self.lo.x, self.nx);
        let y = self.index(lo.y, self.lo.y, self.ny);
        y * self.nx + x == c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point2<f64> {
        Point2::new(x, y)
    }

    /// Arranges `segs` over `pos` with every point in the snapping grid.
    fn run(pos: &[Point2<f64>], segs: &[[u32; 2]], max_crossings: usize) -> Arrangement {
        let mut grid = PointGrid::new(1e-12, pos.len());
        for (i, &q) in pos.iter().enumerate() {
            grid.insert(q, i as u32);
        }
        arrange(pos, segs, &mut grid, pos.len() as u32, max_crossings)
    }

    fn sorted(mut v: Vec<[u32; 2]>) -> Vec<[u32; 2]> {
        for e in &mut v {
            *e = [e[0].min(e[1]), e[0].max(e[1])];
        }
        v.sort_unstable();
        v
    }

    #[test]
    fn crossing_segments_are_cut_at_one_new_point() {
        let pos = [p(0.0, 0.0), p(2.0, 2.0), p(2.0, 0.0), p(0.0, 2.0)];
        let a = run(&pos, &[[0, 1], [2, 3]], 10);
        assert_eq!(a.crossings, [p(1.0, 1.0)]);
        assert_eq!(sorted(a.pieces), [[0, 4], [1, 4], [2, 4], [3, 4]]);
        assert!(a.complete);
        // Without a crossing budget the segments stay whole.
        let a = run(&pos, &[[0, 1], [2, 3]], 0);
        assert_eq!((a.pieces.len(), a.uncut), (2, 1));
    }

    #[test]
    fn vertex_on_a_segment_and_collinear_overlap() {
        // 0–1 along the x axis; 2 lies on it; 3–4 overlaps it from 1.5 to 3.
        let pos = [
            p(0.0, 0.0),
            p(2.0, 0.0),
            p(1.0, 0.0),
            p(1.0, 1.0),
            p(1.5, 0.0),
            p(3.0, 0.0),
        ];
        let a = run(&pos, &[[0, 1], [2, 3], [4, 5]], 10);
        assert!(a.crossings.is_empty());
        assert_eq!(sorted(a.pieces), [[0, 2], [1, 4], [1, 5], [2, 3], [2, 4]]);
    }

    #[test]
    fn concurrent_crossings_share_one_point() {
        // Three segments through (1, 1): one crossing vertex, six pieces.
        let pos = [
            p(0.0, 0.0),
            p(2.0, 2.0),
            p(2.0, 0.0),
            p(0.0, 2.0),
            p(1.0, -1.0),
            p(1.0, 3.0),
        ];
        let a = run(&pos, &[[0, 1], [2, 3], [4, 5]], 10);
        assert_eq!(a.crossings.len(), 1);
        assert_eq!(a.pieces.len(), 6);
    }

    #[test]
    fn many_segments_match_brute_force() {
        // A zigzag with long and short segments; every crossing found by the grid is found
        // by testing all pairs, and the other way round.
        let pos: Vec<Point2<f64>> = (0..300)
            .map(|i| {
                let t = i as f64 * 2.399;
                p(
                    t.cos() * (1.0 + (i % 7) as f64),
                    t.sin() * (1.0 + (i % 5) as f64),
                )
            })
            .collect();
        let segs: Vec<[u32; 2]> = (0..299).map(|i| [i, i + 1]).collect();
        let a = run(&pos, &segs, usize::MAX);
        let mut brute = 0;
        for s in 0..segs.len() {
            for t in s + 1..segs.len() {
                let [[a0, a1], [b0, b1]] = [segs[s], segs[t]].map(|e| e.map(|i| pos[i as usize]));
                let shared = segs[s].iter().any(|v| segs[t].contains(v));
                brute += usize::from(!shared && crossing([a0, a1], [b0, b1], 1e-12).is_some());
            }
        }
        assert!(brute > 100);
        assert_eq!(a.crossings.len(), brute);
        assert!(a.complete);
    }
}
