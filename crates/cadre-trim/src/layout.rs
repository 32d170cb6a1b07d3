//! The trim trees of many faces in the compact words a GPU reads (a `u32` per node, `f32`
//! records per piece and per two-piece leaf), and the CPU classifier on the same words: the
//! oracle the GPU's per-fragment test will be checked against.
//!
//! Coordinates are face-local: each face's (u, v) minus its tree's lower corner, in `f32`, so
//! that a face far from the parameter origin (a B-spline's v in millimetres, say) keeps its
//! precision.
//!
//! A node is one word: kind in bits 29–31 ([`KIND_SPLIT`] …), the coverage bit in bit 28,
//! a payload in bits 0–27 (a split's first child, relative to the face's first node; a
//! constant's value; a piece, relative to the face's first piece; a two-piece record's offset
//! in `floats`; an [`KIND_ALL`] root's piece count). A piece is its three control points
//! from its offset — two, its ends, where it is straight ([`PIECE_LINE`]: its control point
//! is the chord's middle, 62 % of the corpus' pieces) — and a piece that starts where the one
//! before it ends (bit for bit: the pieces of a loop, in order) shares that point, so a loop
//! of n curved pieces takes 2n + 1 points, not 3n. A point is one word where the face's tree
//! was built on its grid ([`PIECE_ON_GRID`]: its u and v indices on the root cell's 2¹⁶ × 2¹⁶
//! grid, the point `f32(k) · size / 2¹⁶`, computed alike on the CPU and the GPU — the corpus'
//! trees take 33 B a trim curve at 0.1 mm and 48 B at 0.01 mm so, against 42 B and 54 B with
//! every point in two `f32`), else two face-local `f32`. Its implicit form is worked out from
//! the points where it is read (a 2 × 2 solve), not stored, and its offset word in
//! `piece_offsets` carries whether it is straight, whether its form's sign is turned over
//! ([`PIECE_NEGATIVE`]) and whether it is on the grid.
//! A two-piece record is the line (nx, ny, d) and the two pieces' indices as `f32` bits. A
//! fallback leaf's payload is its record's offset in `lists`: a word of its piece count with
//! its corner's answer in bit 31 ([`LIST_CORNER`]), then its pieces.

use crate::Uv;
use crate::quadtree::{GENERIC, Leaf, Node, TrimTree, grid_index, grid_point, grid_step};

/// Node kinds (bits 29–31).
pub const KIND_SPLIT: u32 = 0;
/// A cell wholly on (payload 1) or off (0) the face.
pub const KIND_CONSTANT: u32 = 1;
/// One piece decides.
pub const KIND_ONE: u32 = 2;
/// Two pieces and a line.
pub const KIND_TWO: u32 = 3;
/// The crossing parity over a cell's pieces.
pub const KIND_FALLBACK: u32 = 4;
/// A root that is the whole tree ([`crate::quadtree::Leaf::All`]): the parity of the face's
/// pieces (the payload: how many) crossed towards +u.
pub const KIND_ALL: u32 = 5;
/// The coverage bit.
pub const COVERAGE: u32 = 1 << 28;
/// The payload's mask.
pub const PAYLOAD: u32 = (1 << 28) - 1;
/// Most floats (or words) a piece's control points take: three points of two `f32`.
pub const PIECE_FLOATS: usize = 6;
/// A piece's offset word: straight (its form is the signed distance to its chord).
pub const PIECE_LINE: u32 = 1 << 31;
/// A piece's offset word: its form's sign is −1 ([`crate::Implicit::sign`]: the face lies on
/// the side of the parabola away from the control point), decided once in `f64` rather than
/// from the `f32` determinant where the form is read.
pub const PIECE_NEGATIVE: u32 = 1 << 30;
/// A piece's offset word: its points are one word each, indices on its face's grid
/// ([`crate::quadtree::TrimTree::build_on_grid`]: u in the low 16 bits, v in the high; the
/// face-local point is `f32(index) * size / 2¹⁶`), not two `f32`.
pub const PIECE_ON_GRID: u32 = 1 << 29;
/// A piece's offset word: the offset itself.
pub const PIECE_OFFSET: u32 = (1 << 29) - 1;
/// A fallback record's first word: the corner's answer (the count in the other bits).
pub const LIST_CORNER: u32 = 1 << 31;
/// Words per face record on the GPU ([`TrimBuffers::face_words`]).
pub const FACE_WORDS: usize = 4;
/// Floats per two-piece record.
pub const TWO_FLOATS: usize = 5;

/// Where one face's tree lies in the buffers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceRecord {
    /// The tree's lower corner, subtracted from (u, v) before anything else (kept in `f64`
    /// on the CPU; the GPU gets it split into a high and a low `f32`).
    pub origin: Uv,
    /// The root cell's size.
    pub size: [f32; 2],
    /// First node, first piece (its index in pieces, not floats), piece count.
    pub nodes: u32,
    /// First piece.
    pub pieces: u32,
    /// Number of pieces.
    pub piece_count: u32,
}

/// The trees of a set of faces, packed.
#[derive(Clone, Debug, Default)]
pub struct TrimBuffers {
    /// One record per face, in the order added.
    pub faces: Vec<FaceRecord>,
    /// Nodes, a word each.
    pub nodes: Vec<u32>,
    /// Pieces' control points (at most [`PIECE_FLOATS`] each, from 0; a point on its face's
    /// grid is one word, its indices as `f32` bits) and two-piece records, interleaved as
    /// added.
    pub floats: Vec<f32>,
    /// Offset of each piece's record in `floats`, by piece index.
    pub piece_offsets: Vec<u32>,
    /// The fallback leaves' records.
    pub lists: Vec<u32>,
}

/// What a tree says of a cell of the (u, v) domain as a whole
/// ([`TrimBuffers::classify_cell`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellClass {
    /// No point of the cell is on the face.
    Out,
    /// Every point of the cell is on the face.
    In,
    /// Some may be and some not, or the tree does not say without a finer look.
    Crossed,
}

/// Why a tree does not fit the layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LayoutError {
    /// An index past the 28 bits of a payload.
    #[error("a trim tree's index {0} exceeds the layout's 28-bit payload")]
    TooLarge(usize),
}

impl TrimBuffers {
    /// Appends `tree`; returns its face's index.
    pub fn push(&mut self, tree: &TrimTree) -> Result<usize, LayoutError> {
        let origin = tree.bounds.0;
        let size = tree.bounds.1 - origin;
        let record = FaceRecord {
            origin,
            size: [size.x as f32, size.y as f32],
            nodes: self.nodes.len() as u32,
            pieces: self.piece_offsets.len() as u32,
            piece_count: tree.pieces.len() as u32,
        };
        let fits = |x: usize| {
            if x as u64 > u64::from(PAYLOAD) {
                Err(LayoutError::TooLarge(x))
            } else {
                Ok(x as u32)
            }
        };
        fits(self.floats.len() + tree.pieces.len() * PIECE_FLOATS + tree.nodes.len() * 5)?;
        // Where the last point written starts, if this face wrote one.
        let mut last: Option<usize> = None;
        let step = [grid_step(record.size[0]), grid_step(record.size[1])];
        // A point's words: one on the grid (its indices, u low), else two `f32`.
        let words = |p: Uv| -> ([f32; 2], usize) {
            let l = p - origin;
            if tree.on_grid {
                let k = grid_index(l, step);
                ([f32::from_bits(k[0] | k[1] << 16), 0.0], 1)
            } else {
                ([l.x as f32, l.y as f32], 2)
            }
        };
        for (piece, form) in tree.pieces.iter().zip(&tree.forms) {
            let (start, n) = words(piece.p[0]);
            let shared = last
                .filter(|&at| (0..n).all(|i| self.floats[at + i].to_bits() == start[i].to_bits()));
            let at = match shared {
                Some(at) => at,
                None => {
                    self.floats.extend_from_slice(&start[..n]);
                    self.floats.len() - n
                }
            };
            if at as u64 > u64::from(PIECE_OFFSET) {
                return Err(LayoutError::TooLarge(at));
            }
            if !form.line {
                self.floats.extend_from_slice(&words(piece.p[1]).0[..n]);
            }
            self.floats.extend_from_slice(&words(piece.p[2]).0[..n]);
            last = Some(self.floats.len() - n);
            let mut word = at as u32;
            if form.line {
                word |= PIECE_LINE;
            }
            if form.sign < 0.0 {
                word |= PIECE_NEGATIVE;
            }
            if tree.on_grid {
                word |= PIECE_ON_GRID;
            }
            self.piece_offsets.push(word);
        }
        // The cells as the GPU walks them (halved in `f32` from the root), for the fallback
        // leaves' corner answers.
        let mut cells = vec![([0.0f32; 2], record.size); tree.nodes.len()];
        for (i, node) in tree.nodes.iter().enumerate() {
            if let Node::Split { first, .. } = *node {
                let (lo, hi) = cells[i];
                let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
                for k in 0..4usize {
                    let (right, up) = (k & 1 != 0, k & 2 != 0);
                    cells[first as usize + k] = (
                        [
                            if right { mid[0] } else { lo[0] },
                            if up { mid[1] } else { lo[1] },
                        ],
                        [
                            if right { hi[0] } else { mid[0] },
                            if up { hi[1] } else { mid[1] },
                        ],
                    );
                }
            }
        }
        for (i, node) in tree.nodes.iter().enumerate() {
            let word = match *node {
                Node::Split { first, coverage } => {
                    KIND_SPLIT << 29 | u32::from(coverage) << 28 | fits(first as usize)?
                }
                Node::Leaf { leaf, coverage } => {
                    let (kind, payload) = match leaf {
                        Leaf::Constant(on) => (KIND_CONSTANT, u32::from(on)),
                        Leaf::One(k) => (KIND_ONE, fits(k as usize)?),
                        Leaf::All => (KIND_ALL, fits(tree.pieces.len())?),
                        Leaf::Two { line, pieces } => {
                            let at = fits(self.floats.len())?;
                            let d = line.1 - line.0.dot(origin);
                            self.floats.extend([
                                line.0.x as f32,
                                line.0.y as f32,
                                d as f32,
                                f32::from_bits(pieces[0]),
                                f32::from_bits(pieces[1]),
                            ]);
                            (KIND_TWO, at)
                        }
                        Leaf::Fallback { first, count, .. } => {
                            let at = fits(self.lists.len())?;
                            let pieces = &tree.lists[first as usize..(first + count) as usize];
                            // The tree's corner answer, worked out again with the words'
                            // `f32` crossings (a piece through the corner may count otherwise
                            // there than in `f64`).
                            let (lo, hi) = cells[i];
                            let q = [
                                lo[0] + GENERIC[0] as f32 * (hi[0] - lo[0]),
                                lo[1] + GENERIC[1] as f32 * (hi[1] - lo[1]),
                            ];
                            let at_q =
                                tree.parity(origin + Uv::new(f64::from(q[0]), f64::from(q[1])));
                            let corner = at_q
                                ^ self.crossings_to_corner(record, pieces.iter().copied(), q, hi);
                            self.lists
                                .push(count | if corner { LIST_CORNER } else { 0 });
                            self.lists.extend_from_slice(pieces);
                            (KIND_FALLBACK, at)
                        }
                    };
                    kind << 29 | u32::from(coverage) << 28 | payload
                }
            };
            self.nodes.push(word);
        }
        self.faces.push(record);
        Ok(self.faces.len() - 1)
    }

    /// The face records as the GPU reads them (`TrimFace` in trim.wgsl: size as `f32` bits,
    /// first node, first piece).
    pub fn face_words(&self) -> Vec<[u32; FACE_WORDS]> {
        self.faces
            .iter()
            .map(|f| [f.size[0].to_bits(), f.size[1].to_bits(), f.nodes, f.pieces])
            .collect()
    }

    /// Bytes of the trees as the GPU holds them: nodes, floats, pieces' offset words,
    /// fallback records and the face records.
    pub fn bytes(&self) -> usize {
        self.bytes_by_buffer().iter().map(|(_, bytes)| bytes).sum()
    }

    /// [`TrimBuffers::bytes`] by buffer: nodes, floats (control points and two-piece
    /// records), pieces' offset words, fallback records, face records.
    pub fn bytes_by_buffer(&self) -> [(&'static str, usize); 5] {
        [
            ("nodes", 4 * self.nodes.len()),
            ("floats", 4 * self.floats.len()),
            ("piece_offsets", 4 * self.piece_offsets.len()),
            ("lists", 4 * self.lists.len()),
            ("faces", 4 * FACE_WORDS * self.faces.len()),
        ]
    }

    /// What the tree of face `face` says of the face-local cell `lo`..`hi` as a whole (as
    /// `trim_cell` in trim.wgsl, its GPU twin): the walk follows the cell down while one
    /// child holds it; at a constant leaf it knows, at another leaf it knows when none of
    /// the leaf's pieces meets the cell (their control points' box misses it: the boundary
    /// does not enter the cell, so its centre answers for all); anything else is
    /// [`CellClass::Crossed`].
    pub fn classify_cell(&self, face: usize, lo: [f32; 2], hi: [f32; 2]) -> CellClass {
        let f = self.faces[face];
        if hi[0] < 0.0 || hi[1] < 0.0 || lo[0] > f.size[0] || lo[1] > f.size[1] {
            return CellClass::Out;
        }
        if lo[0] < 0.0 || lo[1] < 0.0 || hi[0] > f.size[0] || hi[1] > f.size[1] {
            return CellClass::Crossed;
        }
        let (mut nlo, mut nhi) = ([0.0f32; 2], f.size);
        let mut index = f.nodes as usize;
        for _ in 0..=crate::quadtree::MAX_DEPTH {
            let word = self.nodes[index];
            let payload = word & PAYLOAD;
            let pieces: Vec<u32> = match word >> 29 {
                KIND_CONSTANT if payload != 0 => return CellClass::In,
                KIND_CONSTANT => return CellClass::Out,
                KIND_SPLIT => Vec::new(),
                KIND_ONE => vec![payload],
                KIND_TWO => {
                    let r = payload as usize;
                    vec![self.floats[r + 3].to_bits(), self.floats[r + 4].to_bits()]
                }
                KIND_ALL => (0..payload).collect(),
                _ => {
                    let at = payload as usize;
                    let count = (self.lists[at] & !LIST_CORNER) as usize;
                    self.lists[at + 1..at + 1 + count].to_vec()
                }
            };
            if word >> 29 != KIND_SPLIT {
                if pieces.iter().any(|&k| self.piece_meets(f, k, lo, hi)) {
                    return CellClass::Crossed;
                }
                let centre = f.origin
                    + Uv::new(
                        f64::from(0.5 * (lo[0] + hi[0])),
                        f64::from(0.5 * (lo[1] + hi[1])),
                    );
                return if self.classify(face, centre) {
                    CellClass::In
                } else {
                    CellClass::Out
                };
            }
            let mid = [0.5 * (nlo[0] + nhi[0]), 0.5 * (nlo[1] + nhi[1])];
            let right = [lo[0] >= mid[0], lo[1] >= mid[1]];
            let left = [hi[0] <= mid[0], hi[1] <= mid[1]];
            if !((right[0] || left[0]) && (right[1] || left[1])) {
                return CellClass::Crossed;
            }
            index = f.nodes as usize
                + (word & PAYLOAD) as usize
                + usize::from(right[0])
                + 2 * usize::from(right[1]);
            for a in 0..2 {
                if right[a] {
                    nlo[a] = mid[a];
                } else {
                    nhi[a] = mid[a];
                }
            }
        }
        CellClass::Crossed
    }

    /// Whether piece `k` of face `f` may meet the face-local cell `lo`..`hi`: its control
    /// triangle does (no separating axis among the box's two and the triangle's three edge
    /// normals; a straight piece's triangle is its chord).
    fn piece_meets(&self, f: FaceRecord, k: u32, lo: [f32; 2], hi: [f32; 2]) -> bool {
        let (_, c) = self.piece_points(f, k);
        let boxes = (0..2).all(|a| {
            let (x0, x1, x2) = (c[a], c[2 + a], c[4 + a]);
            x0.min(x1).min(x2) <= hi[a] && x0.max(x1).max(x2) >= lo[a]
        });
        let points = [[c[0], c[1]], [c[2], c[3]], [c[4], c[5]]];
        let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
        let half = [0.5 * (hi[0] - lo[0]), 0.5 * (hi[1] - lo[1])];
        let dot = |n: [f32; 2], p: [f32; 2]| n[0] * p[0] + n[1] * p[1];
        boxes
            && (0..3).all(|e| {
                let (a, b) = (points[e], points[(e + 1) % 3]);
                let n = [a[1] - b[1], b[0] - a[0]];
                let p = points.map(|q| dot(n, q));
                let r = n[0].abs() * half[0] + n[1].abs() * half[1];
                let m = dot(n, centre);
                p[0].min(p[1]).min(p[2]) <= m + r && p[0].max(p[1]).max(p[2]) >= m - r
            })
    }

    /// Whether `p` is on face `face`, read from the words as the GPU reads them (`f32`).
    pub fn classify(&self, face: usize, p: Uv) -> bool {
        self.classify_within(face, p, [0.0; 2])
    }

    /// [`TrimBuffers::classify`] for a pixel whose (u, v) footprint is `footprint`: the walk
    /// stops at the first cell no larger than it in both directions and answers by that
    /// cell's coverage bit (`trim_classify_within` in trim.wgsl, its GPU twin).
    pub fn classify_within(&self, face: usize, p: Uv, footprint: [f32; 2]) -> bool {
        let f = self.faces[face];
        let local = p - f.origin;
        let q = [local.x as f32, local.y as f32];
        if q[0] < 0.0 || q[1] < 0.0 || q[0] > f.size[0] || q[1] > f.size[1] {
            return false;
        }
        let (mut lo, mut hi) = ([0.0f32; 2], f.size);
        let mut index = f.nodes as usize;
        loop {
            let word = self.nodes[index];
            let payload = word & PAYLOAD;
            match word >> 29 {
                KIND_SPLIT if hi[0] - lo[0] <= footprint[0] && hi[1] - lo[1] <= footprint[1] => {
                    return word & COVERAGE != 0;
                }
                KIND_SPLIT => {
                    let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
                    let right = q[0] >= mid[0];
                    let up = q[1] >= mid[1];
                    index = f.nodes as usize
                        + payload as usize
                        + usize::from(right)
                        + 2 * usize::from(up);
                    if right {
                        lo[0] = mid[0]
                    } else {
                        hi[0] = mid[0]
                    }
                    if up { lo[1] = mid[1] } else { hi[1] = mid[1] }
                }
                KIND_CONSTANT => return payload != 0,
                KIND_ONE => return self.value(f, payload, q) >= 0.0,
                KIND_ALL => {
                    // The root's corner is off the face and no piece reaches its edge: the
                    // crossings towards +u alone.
                    return self.crossings_to_corner(f, 0..payload, q, hi);
                }
                KIND_TWO => {
                    let r = &self.floats[payload as usize..payload as usize + TWO_FLOATS];
                    let positive = r[0] * q[0] + r[1] * q[1] >= r[2];
                    let k = if positive { r[3] } else { r[4] }.to_bits();
                    return self.value(f, k, q) >= 0.0;
                }
                _ => {
                    let at = payload as usize;
                    let head = self.lists[at];
                    let (count, corner) = ((head & !LIST_CORNER) as usize, head & LIST_CORNER != 0);
                    let pieces = &self.lists[at + 1..at + 1 + count];
                    return corner ^ self.crossings_to_corner(f, pieces.iter().copied(), q, hi);
                }
            }
        }
    }

    /// How far, in pixels, `p` lies from the trim boundary of face `face` near it, to first
    /// order: the least |F| / |∇F| (the gradient taken to the screen through the pixel's
    /// (u, v) steps `jx`, `jy`) over the pieces of the leaves at the four corners of the
    /// pixel's (u, v) reach about `p` whose box, grown by that reach, holds `p` (a one-piece
    /// leaf's piece whatever its box); `1e30` where none is near (`trim_edge_pixels` in
    /// trim.wgsl, its GPU twin). A trimmed edge's pixel is covered 0.5 + this.
    pub fn edge_pixels(&self, face: usize, p: Uv, jx: [f32; 2], jy: [f32; 2]) -> f32 {
        let f = self.faces[face];
        let local = p - f.origin;
        let q = [local.x as f32, local.y as f32];
        let reach = [jx[0].abs() + jy[0].abs(), jx[1].abs() + jy[1].abs()];
        let mut best = 1e30f32;
        let mut last = u32::MAX;
        for corner in 0..4 {
            let side = [
                if corner & 1 != 0 { 1.0 } else { -1.0 },
                if corner & 2 != 0 { 1.0 } else { -1.0 },
            ];
            let at = [q[0] + side[0] * reach[0], q[1] + side[1] * reach[1]];
            let word = self.leaf_at(f, at);
            if word != last {
                best = best.min(self.leaf_pixels(f, word, q, (jx, jy), reach));
            }
            last = word;
        }
        best
    }

    /// The leaf word of face `f`'s tree at the face-local point `point` (clamped to the
    /// root; `trim_leaf_at`).
    fn leaf_at(&self, f: FaceRecord, point: [f32; 2]) -> u32 {
        let q = [
            point[0].clamp(0.0, f.size[0]),
            point[1].clamp(0.0, f.size[1]),
        ];
        let (mut lo, mut hi) = ([0.0f32; 2], f.size);
        let mut index = f.nodes as usize;
        for _ in 0..=crate::quadtree::MAX_DEPTH {
            let word = self.nodes[index];
            if word >> 29 != KIND_SPLIT {
                return word;
            }
            let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
            let right = q[0] >= mid[0];
            let up = q[1] >= mid[1];
            index = f.nodes as usize
                + (word & PAYLOAD) as usize
                + usize::from(right)
                + 2 * usize::from(up);
            if right {
                lo[0] = mid[0]
            } else {
                hi[0] = mid[0]
            }
            if up { lo[1] = mid[1] } else { hi[1] = mid[1] }
        }
        KIND_CONSTANT << 29
    }

    /// The least distance in pixels from `q` to the pieces of the leaf `word` of `f`
    /// (`trim_leaf_pixels`).
    fn leaf_pixels(
        &self,
        f: FaceRecord,
        word: u32,
        q: [f32; 2],
        steps: ([f32; 2], [f32; 2]),
        reach: [f32; 2],
    ) -> f32 {
        let payload = word & PAYLOAD;
        let near = |k: u32, reach: [f32; 2]| self.piece_pixels(f, k, q, steps, reach);
        match word >> 29 {
            KIND_ONE => near(payload, [1e30; 2]),
            KIND_TWO => {
                let r = payload as usize;
                near(self.floats[r + 3].to_bits(), reach)
                    .min(near(self.floats[r + 4].to_bits(), reach))
            }
            KIND_ALL => (0..payload).map(|k| near(k, reach)).fold(1e30, f32::min),
            KIND_FALLBACK => {
                let at = payload as usize;
                let count = (self.lists[at] & !LIST_CORNER) as usize;
                self.lists[at + 1..at + 1 + count]
                    .iter()
                    .map(|&k| near(k, reach))
                    .fold(1e30, f32::min)
            }
            _ => 1e30,
        }
    }

    /// Piece `k`'s distance from `q` in pixels when `q` lies within its box grown by
    /// `reach`, else `1e30`: beside the piece to first order, past its ends the distance to
    /// the end (`trim_piece_pixels` in trim.wgsl).
    fn piece_pixels(
        &self,
        f: FaceRecord,
        k: u32,
        q: [f32; 2],
        (jx, jy): ([f32; 2], [f32; 2]),
        reach: [f32; 2],
    ) -> f32 {
        let (_, c) = self.piece_points(f, k);
        for a in 0..2 {
            let lo = c[a].min(c[2 + a]).min(c[4 + a]) - reach[a];
            let hi = c[a].max(c[2 + a]).max(c[4 + a]) + reach[a];
            if q[a] < lo || q[a] > hi {
                return 1e30;
            }
        }
        let (value, g, along) = self.value_gradient(f, k, q);
        if !(0.0..=1.0).contains(&along) {
            let end = if along < 0.0 {
                [c[0], c[1]]
            } else {
                [c[4], c[5]]
            };
            let delta = [q[0] - end[0], q[1] - end[1]];
            let det = jx[0] * jy[1] - jx[1] * jy[0];
            let det = if det.abs() < 1e-30 { 1e-30 } else { det };
            let pixels = [
                (jy[1] * delta[0] - jy[0] * delta[1]) / det,
                (jx[0] * delta[1] - jx[1] * delta[0]) / det,
            ];
            return (pixels[0] * pixels[0] + pixels[1] * pixels[1]).sqrt();
        }
        let screen = [g[0] * jx[0] + g[1] * jx[1], g[0] * jy[0] + g[1] * jy[1]];
        value.abs()
            / (screen[0] * screen[0] + screen[1] * screen[1])
                .sqrt()
                .max(1e-30)
    }

    /// Piece `k` of face `f` at `q`: its implicit value (either sign), that value's gradient
    /// in (u, v), and where along the piece `q` lies (0 at its start, 1 at its end: the
    /// Loop–Blinn x, or the projection on the chord), from [`TrimBuffers::classify`]'s form
    /// (`trim_value_gradient` in trim.wgsl).
    pub fn value_gradient(&self, f: FaceRecord, k: u32, q: [f32; 2]) -> (f32, [f32; 2], f32) {
        let (word, c) = self.piece_points(f, k);
        let (e1, e2) = ([c[2] - c[0], c[3] - c[1]], [c[4] - c[0], c[5] - c[1]]);
        let d = [q[0] - c[0], q[1] - c[1]];
        let dot = |a: [f32; 2], b: [f32; 2]| a[0] * b[0] + a[1] * b[1];
        if word & PIECE_LINE != 0 {
            let len = (e2[0] * e2[0] + e2[1] * e2[1]).sqrt();
            let n = [-e2[1] / len, e2[0] / len];
            return (dot(n, d), n, dot(d, e2) / dot(e2, e2));
        }
        let det = e1[0] * e2[1] - e1[1] * e2[0];
        let ga = [e2[1] / det, -e2[0] / det];
        let gb = [-e1[1] / det, e1[0] / det];
        let beta = dot(gb, d);
        let x = 0.5 * dot(ga, d) + beta;
        let gx = [0.5 * ga[0] + gb[0], 0.5 * ga[1] + gb[1]];
        (
            x * x - beta,
            [2.0 * x * gx[0] - gb[0], 2.0 * x * gx[1] - gb[1]],
            x,
        )
    }

    /// Piece `k` of face `f`: its offset word and its three control points (x, y each; a
    /// straight piece's middle one is its chord's middle), as `trim_piece` in trim.wgsl.
    fn piece_points(&self, f: FaceRecord, k: u32) -> (u32, [f32; PIECE_FLOATS]) {
        let word = self.piece_offsets[(f.pieces + k) as usize];
        let at = (word & PIECE_OFFSET) as usize;
        let unpacked: [f32; PIECE_FLOATS];
        let c: &[f32] = if word & PIECE_ON_GRID != 0 {
            // As `trim_grid_point` in trim.wgsl.
            let step = [grid_step(f.size[0]), grid_step(f.size[1])];
            let point = |i: usize| {
                let w = self.floats.get(at + i).map_or(0, |x| x.to_bits());
                grid_point([w & 0xffff, w >> 16], step)
            };
            let (a, b, c) = (point(0), point(1), point(2));
            unpacked = [a[0], a[1], b[0], b[1], c[0], c[1]];
            &unpacked
        } else {
            &self.floats[at..]
        };
        if word & PIECE_LINE != 0 {
            let mid = [0.5 * (c[0] + c[2]), 0.5 * (c[1] + c[3])];
            (word, [c[0], c[1], mid[0], mid[1], c[2], c[3]])
        } else {
            (word, [c[0], c[1], c[2], c[3], c[4], c[5]])
        }
    }

    /// Piece `k` of face `f`'s implicit value at the face-local point `q`, from its control
    /// points (`Implicit::of`'s map, in `f32`).
    fn value(&self, f: FaceRecord, k: u32, q: [f32; 2]) -> f32 {
        let (word, c) = self.piece_points(f, k);
        let (e1, e2) = ([c[2] - c[0], c[3] - c[1]], [c[4] - c[0], c[5] - c[1]]);
        let d = [q[0] - c[0], q[1] - c[1]];
        let value = if word & PIECE_LINE != 0 {
            // Signed distance to the chord, positive on its left.
            (e2[0] * d[1] - e2[1] * d[0]) / (e2[0] * e2[0] + e2[1] * e2[1]).sqrt()
        } else {
            let det = e1[0] * e2[1] - e1[1] * e2[0];
            let alpha = (d[0] * e2[1] - d[1] * e2[0]) / det;
            let beta = (e1[0] * d[1] - e1[1] * d[0]) / det;
            let (x, y) = (0.5 * alpha + beta, beta);
            // x² − y > 0 on the control point's side.
            (x * x - y).min(x - y)
        };
        if word & PIECE_NEGATIVE != 0 {
            -value
        } else {
            value
        }
    }

    /// The parity of `pieces`' crossings from `q` right to the cell's edge, then up the edge
    /// to its corner `hi`, as [`TrimTree`]'s fallback leaves count them.
    fn crossings_to_corner(
        &self,
        f: FaceRecord,
        pieces: impl IntoIterator<Item = u32>,
        q: [f32; 2],
        hi: [f32; 2],
    ) -> bool {
        pieces
            .into_iter()
            .fold(false, |odd, k| odd ^ self.piece_flips(f, k, q, hi))
    }

    /// Whether piece `k` of face `f` turns the answer over on the way from `q` right to the
    /// cell's edge `hi[0]`, then up that edge to the corner `hi`: it crosses one leg and not
    /// the other (`trim_piece_flips` in trim.wgsl, its GPU twin, step for step). A leg that
    /// misses the piece's box, or passes all of it, answers without the bisection.
    fn piece_flips(&self, f: FaceRecord, k: u32, q: [f32; 2], hi: [f32; 2]) -> bool {
        let (_, c) = self.piece_points(f, k);
        let points = [[c[0], c[1]], [c[2], c[3]], [c[4], c[5]]];
        let box_lo = [c[0].min(c[2]).min(c[4]), c[1].min(c[3]).min(c[5])];
        let box_hi = [c[0].max(c[2]).max(c[4]), c[1].max(c[3]).max(c[5])];
        let mut flips = false;
        // Right along v = q[1], from q[0] to hi[0].
        if c[1].min(c[5]) <= q[1] && q[1] < c[1].max(c[5]) {
            if q[0] < box_lo[0] && box_hi[0] <= hi[0] {
                flips = true;
            } else if q[0] < box_hi[0] && box_lo[0] <= hi[0] {
                flips = crossing(points, 1, q[1]).is_some_and(|u| u > q[0] && u <= hi[0]);
            }
        }
        // Up along u = hi[0], from q[1] to hi[1].
        if c[0].min(c[4]) <= hi[0] && hi[0] < c[0].max(c[4]) {
            let up = if q[1] <= box_lo[1] && box_hi[1] < hi[1] {
                true
            } else if q[1] <= box_hi[1] && box_lo[1] < hi[1] {
                crossing(points, 0, hi[0]).is_some_and(|v| v >= q[1] && v < hi[1])
            } else {
                false
            };
            flips ^= up;
        }
        flips
    }
}

/// Where the monotone piece with control points `c` reaches `value` along `axis`: the other
/// coordinate there, if `value` lies in [its lower end's, its upper end's) (`f32`, as the GPU).
fn crossing(c: [[f32; 2]; 3], axis: usize, value: f32) -> Option<f32> {
    let (a, b) = (c[0][axis], c[2][axis]);
    let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
    if !(lo <= value && value < hi) {
        return None;
    }
    let eval = |t: f32, i: usize| {
        let s = 1.0 - t;
        s * s * c[0][i] + 2.0 * s * t * c[1][i] + t * t * c[2][i]
    };
    let rising = b > a;
    let (mut s, mut t) = (0.0f32, 1.0f32);
    for _ in 0..24 {
        let m = 0.5 * (s + t);
        if (eval(m, axis) < value) == rising {
            s = m;
        } else {
            t = m;
        }
    }
    Some(eval(0.5 * (s + t), 1 - axis))
}
