//! The multiresolution trim quadtree of one face (seed 000, Part III): the (u, v) box of its
//! trim pieces split into cells until each is on the face, off it, crossed by one piece, or
//! crossed by two pieces that a line separates (two pieces meeting at a joint, or two whose
//! boxes a vertical or horizontal line parts). A point is classified by the leaf that holds
//! it: a constant, one implicit form's sign, or the separating line's side then one form.
//! Every node carries whether most of its cell lies on the face, for the fragments whose
//! pixel covers the cell (the stop rule that keeps distant perforated faces free of moiré).
//!
//! Where three or more pieces still meet in a cell deep enough (or two that no line parts),
//! the cell is a fallback leaf, exact and slower: it keeps its pieces and whether its
//! top-right corner is on the face, and a point's answer is the corner's, turned over at each
//! of the cell's pieces crossed on the way from the point right to the cell's edge, then up
//! the edge to the corner (the even-odd rule, counted within the cell).
//! [`TrimTree::fallback_leaves`] counts them, [`TrimTree::capped_leaves`] those the depth cap
//! made (where the thesis gave up instead). Without them a sliver face, two trim curves a
//! micron apart, split every cell along its length down to the depth cap (97,861 nodes for
//! 16 pieces in trj6_b1-ec-214). They are also what keeps the trees small: a cell of at most
//! [`FALLBACK_PIECES`] pieces from [`FALLBACK_DEPTH`] stops there, and a face of at most
//! [`ALL_PIECES`] pieces has no tree beyond its root ([`Leaf::All`]).

use crate::Uv;
use crate::quad::{Implicit, QuadPiece};

/// Depth of the deepest cells (the thesis' cap): 4¹³ cells across a face's box.
pub const MAX_DEPTH: u32 = 13;
/// Depth from which a cell that one or two implicit forms cannot decide becomes a fallback
/// leaf when it holds at most [`FALLBACK_PIECES`] pieces, rather than being split further.
/// Bytes against per-fragment work: the corpus' trees take 45 B a trim curve with fallbacks
/// from depth 2 and 4 pieces, 61 B from depth 3, 91 B from depth 8 with 8 pieces and no
/// [`Leaf::All`] roots (BENCHMARKS.md, "Trim trees of the corpus"); a fallback fragment
/// reads at most four pieces, most rejected by their boxes.
pub const FALLBACK_DEPTH: u32 = 2;
/// Most pieces a fallback leaf takes from [`FALLBACK_DEPTH`].
pub const FALLBACK_PIECES: usize = 4;
/// Depth from which a fallback leaf takes up to [`DEEP_FALLBACK_PIECES`] pieces: where many
/// pieces meet (a vertex of many edges, a sliver face), splitting further only multiplies
/// cells that all hold the same pieces.
pub const DEEP_FALLBACK_DEPTH: u32 = 8;
/// Most pieces a fallback leaf takes from [`DEEP_FALLBACK_DEPTH`] until the depth cap.
pub const DEEP_FALLBACK_PIECES: usize = 8;
/// Where in a fallback cell its corner answer is worked out from (a fraction of the cell
/// along u and v): a point no trim feature is likely to meet.
pub const GENERIC: [f64; 2] = [0.618_033_988_749_894_9, 0.381_966_011_250_105_1];
/// Most pieces of a face whose tree is its root alone, a [`Leaf::All`]: the even-odd rule
/// over all its pieces. Most CAD faces are bounded by a handful of curves (a rectangle, a
/// cylinder's two circles and seam: 82 % of the corpus' faces), and their trees cost more
/// bytes than their pieces; a fragment reads at most this many pieces, each rejected by its
/// box but the one or two its row meets.
pub const ALL_PIECES: usize = 8;

/// How a leaf classifies its points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Leaf {
    /// The whole cell is on the face (`true`) or off it.
    Constant(bool),
    /// One piece crosses the cell: on the face where its form is ≥ 0.
    One(u32),
    /// Two pieces, parted by the line `n · p ≥ d`: the first piece decides on that side, the
    /// second on the other.
    Two {
        /// The separating line's normal and offset.
        line: (Uv, f64),
        /// The pieces on the line's positive and negative sides.
        pieces: [u32; 2],
    },
    /// The root of a face of at most [`ALL_PIECES`] pieces: the parity of all the pieces
    /// crossed by the ray from the point towards +u (the even-odd rule, [`TrimTree::parity`]).
    All,
    /// Pieces no line parts: the corner's answer and the crossings within the cell.
    Fallback {
        /// The answer at the cell's top-right corner as the crossings count it (turned over
        /// by them, it gives each point's; [`TrimTree::corner_answer`]).
        corner: bool,
        /// The cell's pieces: `count` entries of [`TrimTree::lists`] from `first`.
        first: u32,
        /// How many.
        count: u32,
    },
}

/// A node: a leaf or four children (index of the first; the others follow, in the order
/// (low u, low v), (high u, low v), (low u, high v), (high u, high v)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Node {
    /// Split into four.
    Split {
        /// Index of the first child in [`TrimTree::nodes`].
        first: u32,
        /// Whether most of the cell is on the face.
        coverage: bool,
    },
    /// A leaf.
    Leaf {
        /// How it classifies.
        leaf: Leaf,
        /// Whether most of the cell is on the face.
        coverage: bool,
    },
}

/// One face's trim tree over its monotone pieces.
#[derive(Clone, Debug)]
pub struct TrimTree {
    /// The face's pieces, each monotone in u and in v, the face on their left.
    pub pieces: Vec<QuadPiece>,
    /// Their implicit forms, by index.
    pub forms: Vec<Implicit>,
    /// The cells' box: the root cell.
    pub bounds: (Uv, Uv),
    /// Nodes, the root first.
    pub nodes: Vec<Node>,
    /// The fallback leaves' pieces.
    pub lists: Vec<u32>,
    /// Whether every control point lies on the root's 2¹⁶ × 2¹⁶ grid (at [`grid_local`] of
    /// its indices): the layout then packs a point into one word ([`crate::layout`]).
    pub on_grid: bool,
}

/// Steps of the grid of [`TrimTree::build_on_grid`] along each axis of the root cell.
pub const GRID_STEPS: u32 = 1 << 16;

/// The root cell's size as the layout and the GPU hold it (`f32`).
pub fn grid_size(bounds: (Uv, Uv)) -> [f32; 2] {
    let size = bounds.1 - bounds.0;
    [size.x as f32, size.y as f32]
}

/// The grid's step along an axis of root size `size`: `size / 2¹⁶`, exact in `f32`, so that
/// the GPU's `f32(k) * step` is the CPU's bit for bit.
pub fn grid_step(size: f32) -> f32 {
    size * (1.0 / GRID_STEPS as f32)
}

/// The grid point nearest the root-local point `local` (clamped to the grid: the last step
/// stops short of the root's upper edge).
pub fn grid_index(local: Uv, step: [f32; 2]) -> [u32; 2] {
    let index = |x: f64, s: f32| {
        (x / f64::from(s))
            .round()
            .clamp(0.0, f64::from(GRID_STEPS - 1)) as u32
    };
    [index(local.x, step[0]), index(local.y, step[1])]
}

/// The root-local position of grid point `k` in `f32`, as the GPU computes it
/// (`f32(k) * step`, `trim_grid_point` in trim.wgsl).
pub fn grid_point(k: [u32; 2], step: [f32; 2]) -> [f32; 2] {
    [k[0] as f32 * step[0], k[1] as f32 * step[1]]
}

/// [`grid_point`] in `f64`, where the tree's pieces are moved to.
pub fn grid_local(k: [u32; 2], step: [f32; 2]) -> Uv {
    let [u, v] = grid_point(k, step);
    Uv::new(f64::from(u), f64::from(v))
}

impl TrimTree {
    /// The tree of the loops made of `pieces` (closed loops, the face on each piece's left:
    /// outer loops counter-clockwise, holes clockwise; the face is what they enclose by the
    /// even-odd rule). Pieces are cut into monotone parts first.
    pub fn build(pieces: &[QuadPiece]) -> TrimTree {
        Self::build_on_grid(pieces, None)
    }

    /// [`TrimTree::build`], with every control point moved onto the root cell's grid of
    /// [`GRID_STEPS`] steps a side when that step is within `step_within` (u, v) of a point
    /// (a point moves by at most a step): the layout then packs each point into one 32-bit
    /// word, half the bytes of two `f32`. Snapping keeps a piece monotone (rounding keeps
    /// order) and consecutive pieces joined (a joint snaps once); a piece it shrinks to a
    /// point is dropped, one it straightens becomes a line ([`Implicit::of`]).
    pub fn build_on_grid(
        pieces: &[QuadPiece],
        step_within: Option<crate::UvTolerance>,
    ) -> TrimTree {
        let mut pieces: Vec<QuadPiece> = pieces.iter().flat_map(|p| p.monotone_parts()).collect();
        close_joints(&mut pieces);
        let (mut lo, mut hi) = (Uv::splat(f64::INFINITY), Uv::splat(f64::NEG_INFINITY));
        for p in &pieces {
            let (a, b) = p.bounds();
            lo = lo.min(a);
            hi = hi.max(b);
        }
        if pieces.is_empty() {
            (lo, hi) = (Uv::ZERO, Uv::ZERO);
        }
        // A margin so that no piece runs along the root's border.
        let pad = 1e-6 * (hi - lo).max_element().max(1e-9);
        let bounds = (lo - pad, hi + pad);
        let size = grid_size(bounds);
        let step = [grid_step(size[0]), grid_step(size[1])];
        let on_grid = !pieces.is_empty()
            && step_within.is_some_and(|t| {
                f64::from(step[0]) <= t.u
                    && f64::from(step[1]) <= t.v
                    && step[0] > 0.0
                    && step[1] > 0.0
            });
        if on_grid {
            let snap = |p: Uv| {
                let k = grid_index(p - bounds.0, step);
                bounds.0 + grid_local(k, step)
            };
            for piece in &mut pieces {
                piece.p = piece.p.map(snap);
            }
            pieces.retain(|piece| piece.p[0] != piece.p[2]);
        }
        let forms = pieces.iter().map(QuadPiece::implicit).collect();
        let mut tree = TrimTree {
            pieces,
            forms,
            on_grid,
            bounds,
            nodes: vec![Node::Leaf {
                leaf: Leaf::Constant(false),
                coverage: false,
            }],
            lists: Vec::new(),
        };
        let all: Vec<u32> = (0..tree.pieces.len() as u32).collect();
        tree.build_node(0, tree.bounds, &all, 0);
        tree
    }

    /// Fills node `index` for `cell`, crossed by (at most) the pieces `crossing`; returns the
    /// share of the cell on the face (4 × 4 samples per leaf, the children's mean above).
    fn build_node(&mut self, index: usize, cell: (Uv, Uv), crossing: &[u32], depth: u32) -> f64 {
        let inside: Vec<u32> = crossing
            .iter()
            .copied()
            .filter(|&k| crosses(&self.pieces[k as usize], cell))
            .collect();
        let leaf = match inside.len() {
            0 => Some(Leaf::Constant(self.parity(0.5 * (cell.0 + cell.1)))),
            1 => Some(Leaf::One(inside[0])),
            n if depth == 0 && n <= ALL_PIECES => Some(Leaf::All),
            2 => self.separating_line(inside[0], inside[1], cell),
            _ => None,
        };
        let few = (depth >= FALLBACK_DEPTH && inside.len() <= FALLBACK_PIECES)
            || (depth >= DEEP_FALLBACK_DEPTH && inside.len() <= DEEP_FALLBACK_PIECES);
        let leaf = match leaf {
            Some(leaf) => leaf,
            None if few || depth >= MAX_DEPTH => {
                // Every piece near the cell, not only those crossing it: the GPU walks the
                // cells in `f32`, whose edges lie up to a few 10⁻⁸ of the root off these,
                // and a piece along an edge (a seam, a line at a round parameter) missed
                // here would be crossed there by the way to the corner.
                let near = self.pieces_near(cell);
                let first = self.lists.len() as u32;
                self.lists.extend_from_slice(&near);
                Leaf::Fallback {
                    corner: self.corner_answer(&near, cell),
                    first,
                    count: near.len() as u32,
                }
            }
            None => {
                let first = self.nodes.len() as u32;
                self.nodes.extend([self.nodes[index]; 4]);
                let mid = 0.5 * (cell.0 + cell.1);
                let mut share = 0.0;
                for (k, quarter) in quarters(cell, mid).into_iter().enumerate() {
                    share +=
                        0.25 * self.build_node(first as usize + k, quarter, &inside, depth + 1);
                }
                self.nodes[index] = Node::Split {
                    first,
                    coverage: share >= 0.5,
                };
                return share;
            }
        };
        let mut on = 0;
        for i in 0..4 {
            for j in 0..4 {
                let f = Uv::new((f64::from(i) + 0.5) / 4.0, (f64::from(j) + 0.5) / 4.0);
                if self.leaf_classify(leaf, cell, cell.0 + f * (cell.1 - cell.0)) {
                    on += 1;
                }
            }
        }
        let share = f64::from(on) / 16.0;
        self.nodes[index] = Node::Leaf {
            leaf,
            coverage: share >= 0.5,
        };
        share
    }

    /// A line parting pieces `a` and `b` within `cell`: through their joint where they meet
    /// (across the corner's bisector, or square to a smooth joint), else between their boxes
    /// along u or v. The leaf it makes, or `None` to subdivide.
    fn separating_line(&self, a: u32, b: u32, cell: (Uv, Uv)) -> Option<Leaf> {
        let (pa, pb) = (&self.pieces[a as usize], &self.pieces[b as usize]);
        // A joint: b follows a, or a follows b (ends within a hair of each other: a loop's
        // closing point may differ from its first by rounding).
        let hair = 1e-9 * (cell.1 - cell.0).max_element();
        let joint = if (pa.p[2] - pb.p[0]).length() <= hair {
            Some((a, b))
        } else if (pb.p[2] - pa.p[0]).length() <= hair {
            Some((b, a))
        } else {
            None
        };
        if let Some((incoming, outgoing)) = joint {
            let (pi, po) = (
                &self.pieces[incoming as usize],
                &self.pieces[outgoing as usize],
            );
            let at = 0.5 * (pi.p[2] + po.p[0]);
            let t_in = pi.derivative(1.0).normalize_or_zero();
            let t_out = po.derivative(0.0).normalize_or_zero();
            let bisector = t_out - t_in;
            // The line through the joint along the corner's bisector, or square to the
            // tangent where the joint is smooth (the bisector vanishes).
            let along = if bisector.length() > 1e-6 {
                bisector.normalize()
            } else {
                t_out.perp()
            };
            let n = along.perp();
            // Each piece on one side: its far end decides which.
            let side = |p: Uv| n.dot(p - at);
            let (far_in, far_out) = (side(pi.p[0]), side(po.p[2]));
            if far_in * far_out < 0.0 && self.piece_side(pi, n, at) && self.piece_side(po, n, at) {
                let (positive, negative) = if far_out > 0.0 {
                    (outgoing, incoming)
                } else {
                    (incoming, outgoing)
                };
                return Some(Leaf::Two {
                    line: (n, n.dot(at)),
                    pieces: [positive, negative],
                });
            }
            return None;
        }
        // Boxes parted along u or v inside the cell.
        let (ba, bb) = (pa.bounds(), pb.bounds());
        for axis in 0..2 {
            let (first, second, gap) = if ba.1[axis] < bb.0[axis] {
                (a, b, 0.5 * (ba.1[axis] + bb.0[axis]))
            } else if bb.1[axis] < ba.0[axis] {
                (b, a, 0.5 * (bb.1[axis] + ba.0[axis]))
            } else {
                continue;
            };
            if gap <= cell.0[axis] || gap >= cell.1[axis] {
                continue;
            }
            let n = if axis == 0 { Uv::X } else { Uv::Y };
            return Some(Leaf::Two {
                line: (n, gap),
                pieces: [second, first],
            });
        }
        None
    }

    /// Whether all of `piece` (its control polygon, which holds it) lies on one side of the
    /// line through `at` with normal `n`, touching it only at `at`.
    fn piece_side(&self, piece: &QuadPiece, n: Uv, at: Uv) -> bool {
        let s: Vec<f64> = piece.p.iter().map(|p| n.dot(*p - at)).collect();
        let scale = piece
            .p
            .iter()
            .map(|p| (*p - at).length())
            .fold(0.0, f64::max);
        let eps = 1e-12 * scale.max(1e-300);
        s.iter().all(|&x| x >= -eps) || s.iter().all(|&x| x <= eps)
    }

    /// Whether `p` is on the face by the even-odd rule: the parity of the pieces crossed by
    /// the ray from `p` towards +u (each monotone piece crossed at most once; a piece counts
    /// where the ray's v lies in [its lower end's v, its upper end's v), so a joint counts
    /// once and a horizontal piece never).
    pub fn parity(&self, p: Uv) -> bool {
        let mut inside = false;
        for piece in &self.pieces {
            if crossing(piece, 1, p.y).is_some_and(|u| u > p.x) {
                inside = !inside;
            }
        }
        inside
    }

    /// The parity of the crossings of `pieces` on the way from `p` right to the edge of the
    /// cell whose top-right corner is `corner`, then up that edge to the corner: what turns
    /// the corner's answer into `p`'s (the pieces that do not meet the cell cannot cross a
    /// path inside it).
    fn crossings_to_corner(&self, pieces: &[u32], p: Uv, corner: Uv) -> bool {
        let mut odd = false;
        for &k in pieces {
            let piece = &self.pieces[k as usize];
            if crossing(piece, 1, p.y).is_some_and(|u| u > p.x && u <= corner.x) {
                odd = !odd;
            }
            if crossing(piece, 0, corner.x).is_some_and(|v| v >= p.y && v < corner.y) {
                odd = !odd;
            }
        }
        odd
    }

    /// The pieces that meet `cell` grown by 10⁻⁶ of the root's size.
    fn pieces_near(&self, cell: (Uv, Uv)) -> Vec<u32> {
        let margin = 1e-6 * (self.bounds.1 - self.bounds.0).max_element();
        let grown = (cell.0 - margin, cell.1 + margin);
        (0..self.pieces.len() as u32)
            .filter(|&k| {
                let (lo, hi) = self.pieces[k as usize].bounds();
                lo.cmple(grown.1).all()
                    && hi.cmpge(grown.0).all()
                    && crosses(&self.pieces[k as usize], grown)
            })
            .collect()
    }

    /// A fallback leaf's corner answer: not the even-odd rule at the corner itself, which
    /// may lie on a piece (quadtree corners fall on symmetric features: a hole's top, an
    /// edge along a cell's side), but the answer at a generic point of the cell turned over
    /// by its crossings on the way to the corner — so that every point of the cell, counted
    /// the same way, gets its own answer whatever the rules decide at the corner.
    fn corner_answer(&self, pieces: &[u32], cell: (Uv, Uv)) -> bool {
        let q = cell.0 + Uv::from(GENERIC) * (cell.1 - cell.0);
        self.parity(q) ^ self.crossings_to_corner(pieces, q, cell.1)
    }

    /// Whether `p` is on the face, read from the tree.
    pub fn classify(&self, p: Uv) -> bool {
        let (mut lo, mut hi) = self.bounds;
        if p.x < lo.x || p.y < lo.y || p.x > hi.x || p.y > hi.y {
            return false;
        }
        let mut index = 0usize;
        loop {
            match self.nodes[index] {
                Node::Split { first, .. } => {
                    let mid = 0.5 * (lo + hi);
                    let right = p.x >= mid.x;
                    let up = p.y >= mid.y;
                    index = first as usize + usize::from(right) + 2 * usize::from(up);
                    (lo, hi) = quarters((lo, hi), mid)[usize::from(right) + 2 * usize::from(up)];
                }
                Node::Leaf { leaf, .. } => return self.leaf_classify(leaf, (lo, hi), p),
            }
        }
    }

    /// Whether `p`, in `leaf`'s `cell`, is on the face.
    fn leaf_classify(&self, leaf: Leaf, cell: (Uv, Uv), p: Uv) -> bool {
        match leaf {
            Leaf::Constant(on) => on,
            Leaf::One(k) => self.forms[k as usize].value(p) >= 0.0,
            Leaf::Two { line, pieces } => {
                let k = if line.0.dot(p) >= line.1 {
                    pieces[0]
                } else {
                    pieces[1]
                };
                self.forms[k as usize].value(p) >= 0.0
            }
            Leaf::All => self.parity(p),
            Leaf::Fallback {
                corner,
                first,
                count,
            } => {
                let pieces = &self.lists[first as usize..(first + count) as usize];
                corner ^ self.crossings_to_corner(pieces, p, cell.1)
            }
        }
    }

    /// How many fallback leaves the depth cap made (more than [`DEEP_FALLBACK_PIECES`]
    /// pieces still meeting in a cell of the deepest level: where the thesis gave up).
    pub fn capped_leaves(&self) -> usize {
        self.nodes
            .iter()
            .filter(|n| {
                matches!(
                    n,
                    Node::Leaf {
                        leaf: Leaf::Fallback { count, .. },
                        ..
                    } if *count as usize > DEEP_FALLBACK_PIECES
                )
            })
            .count()
    }

    /// How many leaves fell back to the crossing parity.
    pub fn fallback_leaves(&self) -> usize {
        self.nodes
            .iter()
            .filter(|n| {
                matches!(
                    n,
                    Node::Leaf {
                        leaf: Leaf::Fallback { .. },
                        ..
                    }
                )
            })
            .count()
    }
}

/// Where the monotone `piece` reaches `value` along `axis` (0: u, 1: v): the other
/// coordinate there, if `value` lies in [its lower end's, its upper end's) along that axis.
fn crossing(piece: &QuadPiece, axis: usize, value: f64) -> Option<f64> {
    let (a, b) = (piece.p[0][axis], piece.p[2][axis]);
    let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
    if !(lo <= value && value < hi) {
        return None;
    }
    Some(piece.eval(param_at(piece, axis, value))[1 - axis])
}

/// The parameter where the monotone `piece`'s coordinate `axis` reaches `value`, by bisection
/// (`value` between its ends' coordinates).
fn param_at(piece: &QuadPiece, axis: usize, value: f64) -> f64 {
    let rising = piece.p[2][axis] > piece.p[0][axis];
    let (mut s, mut t) = (0.0, 1.0);
    for _ in 0..52 {
        let m = 0.5 * (s + t);
        if (piece.eval(m)[axis] < value) == rising {
            s = m;
        } else {
            t = m;
        }
    }
    0.5 * (s + t)
}

/// Whether the monotone `piece` meets `cell` (closed, grown by a hair so that touching
/// counts): the parameters where its u lies in the cell's u range and those where its v lies
/// in the v range overlap. Boxes alone would not do: the boxes of a triangle's two slanted
/// sides both hold the middle of its third side, and every cell there would count three
/// pieces down to the depth cap.
fn crosses(piece: &QuadPiece, cell: (Uv, Uv)) -> bool {
    let hair = 1e-9 * (cell.1 - cell.0).max_element();
    let (lo, hi) = (cell.0 - hair, cell.1 + hair);
    let (Some(a), Some(b)) = (
        param_range(piece, 0, lo.x, hi.x),
        param_range(piece, 1, lo.y, hi.y),
    ) else {
        return false;
    };
    a.0.max(b.0) <= a.1.min(b.1)
}

/// The parameters where the monotone `piece`'s coordinate `axis` lies in [lo, hi]: an
/// interval of [0, 1], or none.
fn param_range(piece: &QuadPiece, axis: usize, lo: f64, hi: f64) -> Option<(f64, f64)> {
    let (start, end) = (piece.p[0][axis], piece.p[2][axis]);
    if start.max(end) < lo || start.min(end) > hi {
        return None;
    }
    // The parameter where the coordinate reaches x, clamped to the piece.
    let at = |x: f64| -> f64 {
        let rising = end >= start;
        if (x <= start) == rising {
            0.0
        } else if (x >= end) == rising {
            1.0
        } else {
            param_at(piece, axis, x)
        }
    };
    let (t0, t1) = (at(lo), at(hi));
    Some((t0.min(t1), t0.max(t1)))
}

/// Makes each piece's end equal to the start of a piece within a hair of it (10⁻⁹ of the
/// pieces' box): a loop whose closing point differs from its first by rounding (a circle's
/// sin 2π) would otherwise leave the row through that joint crossed by neither piece, as the
/// even-odd rule counts a piece over [its lower end's v, its upper end's v), and every
/// point of that row would be answered the wrong way by [`Leaf::All`] and fallback leaves.
fn close_joints(pieces: &mut [QuadPiece]) {
    let (mut lo, mut hi) = (Uv::splat(f64::INFINITY), Uv::splat(f64::NEG_INFINITY));
    for p in pieces.iter() {
        for q in p.p {
            lo = lo.min(q);
            hi = hi.max(q);
        }
    }
    let hair = 1e-9 * (hi - lo).max_element();
    if hair.is_nan() || hair <= 0.0 {
        return;
    }
    // The starts sorted by u: an end's candidates lie within a hair of it along u.
    let mut starts: Vec<(f64, usize)> = pieces.iter().map(|p| p.p[0].x).zip(0..).collect();
    starts.sort_by(|a, b| a.0.total_cmp(&b.0));
    for k in 0..pieces.len() {
        let end = pieces[k].p[2];
        let first = starts.partition_point(|s| s.0 < end.x - hair);
        let near = starts[first..]
            .iter()
            .take_while(|s| s.0 <= end.x + hair)
            .map(|&(_, j)| pieces[j].p[0])
            .find(|start| *start != end && (*start - end).length() <= hair);
        if let Some(start) = near {
            pieces[k].p[2] = start;
        }
    }
}

/// The four quarters of `cell` about `mid`, in child order.
fn quarters(cell: (Uv, Uv), mid: Uv) -> [(Uv, Uv); 4] {
    let (lo, hi) = cell;
    [
        (lo, mid),
        (Uv::new(mid.x, lo.y), Uv::new(hi.x, mid.y)),
        (Uv::new(lo.x, mid.y), Uv::new(mid.x, hi.y)),
        (mid, hi),
    ]
}
