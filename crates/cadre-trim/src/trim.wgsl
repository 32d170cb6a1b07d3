// Trim test on the GPU: whether a face-local (u, v) lies on its face, read from the packed trim
// trees (`cadre_trim::layout`: the words and their meaning are documented there, and
// `TrimBuffers::classify` is this function's CPU twin and oracle). The including shader
// declares the five buffers below at bindings of its choice by defining them before this file
// is appended (WGSL has no includes with parameters): `trim_faces`, `trim_nodes`,
// `trim_floats`, `trim_piece_offsets`, `trim_lists`.

struct TrimFace {
    // The root cell's size; (u, v) arrive face-local (minus the tree's lower corner).
    size: vec2<f32>,
    nodes: u32,
    pieces: u32,
}

const TRIM_KIND_SPLIT: u32 = 0u;
const TRIM_KIND_CONSTANT: u32 = 1u;
const TRIM_KIND_ONE: u32 = 2u;
const TRIM_KIND_TWO: u32 = 3u;
const TRIM_KIND_FALLBACK: u32 = 4u;
// A root that is the whole tree: the parity of the face's pieces (the payload: how many).
const TRIM_KIND_ALL: u32 = 5u;
const TRIM_PAYLOAD: u32 = 0x0fffffffu;
// A node's coverage bit: most of its cell lies on the face.
const TRIM_COVERAGE: u32 = 0x10000000u;
// Depth cap (`quadtree::MAX_DEPTH`) plus the root.
const TRIM_MAX_STEPS: u32 = 14u;

// The offset word of a piece (`cadre_trim::layout`): straight, sign turned over, points on
// the face's grid (a word each), offset.
const TRIM_PIECE_LINE: u32 = 0x80000000u;
const TRIM_PIECE_NEGATIVE: u32 = 0x40000000u;
const TRIM_PIECE_ON_GRID: u32 = 0x20000000u;
const TRIM_PIECE_OFFSET: u32 = 0x1fffffffu;
// A fallback record's first word: its corner's answer in bit 31, its piece count below.
const TRIM_LIST_CORNER: u32 = 0x80000000u;

// A piece's control points and its offset word.
struct TrimPiece {
    c0: vec2<f32>,
    c1: vec2<f32>,
    c2: vec2<f32>,
    word: u32,
}

// The face-local point packed in the word at `at` of a piece on `f`'s grid: its indices (u in
// the low 16 bits) times the grid's step, size / 2^16 (exact), so that the product is the
// CPU's bit for bit.
fn trim_grid_point(f: TrimFace, at: u32) -> vec2<f32> {
    let w = bitcast<u32>(trim_floats[at]);
    let step = f.size * (1.0 / 65536.0);
    return vec2<f32>(f32(w & 0xffffu) * step.x, f32(w >> 16u) * step.y);
}

// Piece `k` of `f`: a straight piece stores its ends alone, its control point is their middle
// (`TrimBuffers::piece_points` is the CPU twin).
fn trim_piece(f: TrimFace, k: u32) -> TrimPiece {
    let word = trim_piece_offsets[f.pieces + k];
    let at = word & TRIM_PIECE_OFFSET;
    if (word & TRIM_PIECE_ON_GRID) != 0u {
        let c0 = trim_grid_point(f, at);
        let next = trim_grid_point(f, at + 1u);
        if (word & TRIM_PIECE_LINE) != 0u {
            return TrimPiece(c0, 0.5 * (c0 + next), next, word);
        }
        return TrimPiece(c0, next, trim_grid_point(f, at + 2u), word);
    }
    let c0 = vec2<f32>(trim_floats[at], trim_floats[at + 1u]);
    let next = vec2<f32>(trim_floats[at + 2u], trim_floats[at + 3u]);
    if (word & TRIM_PIECE_LINE) != 0u {
        return TrimPiece(c0, 0.5 * (c0 + next), next, word);
    }
    return TrimPiece(c0, next, vec2<f32>(trim_floats[at + 4u], trim_floats[at + 5u]), word);
}

// Piece `k` of `f`: its implicit value at `q`, positive on the face's side, worked out from
// its control points (the Loop–Blinn map: p0, p1, p2 to (0, 0), (1/2, 0), (1, 1)).
fn trim_value(f: TrimFace, k: u32, q: vec2<f32>) -> f32 {
    let piece = trim_piece(f, k);
    let word = piece.word;
    let c0 = piece.c0;
    let e1 = piece.c1 - c0;
    let e2 = piece.c2 - c0;
    let d = q - c0;
    let chord = (e2.x * d.y - e2.y * d.x) / length(e2);
    let det = e1.x * e2.y - e1.y * e2.x;
    let alpha = (d.x * e2.y - d.y * e2.x) / det;
    let beta = (e1.x * d.y - e1.y * d.x) / det;
    let x = 0.5 * alpha + beta;
    let curved = min(x * x - beta, x - beta);
    let value = select(curved, chord, (word & TRIM_PIECE_LINE) != 0u);
    return select(value, -value, (word & TRIM_PIECE_NEGATIVE) != 0u);
}

// Where the monotone piece `c` (three control points) reaches `value` along `axis`: the other
// coordinate, or NaN-free -1e30 when `value` is outside [its lower end's, its upper end's).
fn trim_crossing(c0: vec2<f32>, c1: vec2<f32>, c2: vec2<f32>, axis: u32, value: f32) -> vec2<f32> {
    let a = c0[axis];
    let b = c2[axis];
    let lo = min(a, b);
    let hi = max(a, b);
    let rising = b > a;
    var s = 0.0;
    var t = 1.0;
    for (var i = 0u; i < 24u; i++) {
        let m = 0.5 * (s + t);
        let w = 1.0 - m;
        let v = w * w * c0[axis] + 2.0 * w * m * c1[axis] + m * m * c2[axis];
        let below = (v < value) == rising;
        s = select(s, m, below);
        t = select(m, t, below);
    }
    let m = 0.5 * (s + t);
    let w = 1.0 - m;
    let other = w * w * c0[1u - axis] + 2.0 * w * m * c1[1u - axis] + m * m * c2[1u - axis];
    // x: 1 where the piece reaches `value`, 0 where not; y: the other coordinate.
    return vec2<f32>(select(0.0, 1.0, (lo <= value) & (value < hi)), other);
}

// Whether piece `k` of `f` turns the answer over on the way from `q` right to the cell's edge
// `hi.x`, then up that edge to the corner `hi`: it crosses one leg and not the other. Pieces
// whose box the leg misses (or wholly passes) answer without the bisection: most of a face's
// pieces where a fragment reads them all (`TrimBuffers::piece_flips` is the CPU twin).
fn trim_piece_flips(f: TrimFace, k: u32, q: vec2<f32>, hi: vec2<f32>) -> bool {
    let piece = trim_piece(f, k);
    let c0 = piece.c0;
    let c1 = piece.c1;
    let c2 = piece.c2;
    let box_lo = min(c0, min(c1, c2));
    let box_hi = max(c0, max(c1, c2));
    var flips = false;
    // Right along v = q.y, from q.x to hi.x.
    if (min(c0.y, c2.y) <= q.y) & (q.y < max(c0.y, c2.y)) {
        if (q.x < box_lo.x) & (box_hi.x <= hi.x) {
            flips = true;
        } else if (q.x < box_hi.x) & (box_lo.x <= hi.x) {
            let h = trim_crossing(c0, c1, c2, 1u, q.y);
            flips = (h.y > q.x) & (h.y <= hi.x);
        }
    }
    // Up along u = hi.x, from q.y to hi.y.
    if (min(c0.x, c2.x) <= hi.x) & (hi.x < max(c0.x, c2.x)) {
        var up = false;
        if (q.y <= box_lo.y) & (box_hi.y < hi.y) {
            up = true;
        } else if (q.y <= box_hi.y) & (box_lo.y < hi.y) {
            let v = trim_crossing(c0, c1, c2, 0u, hi.x);
            up = (v.y >= q.y) & (v.y < hi.y);
        }
        flips = flips != up;
    }
    return flips;
}

// The parity of the fallback leaf's pieces crossed from `q` right to the cell's edge, then up
// to its corner `hi`.
fn trim_crossings(f: TrimFace, record: u32, q: vec2<f32>, hi: vec2<f32>) -> bool {
    let count = trim_lists[record] & ~TRIM_LIST_CORNER;
    var odd = false;
    for (var i = 0u; i < min(count, arrayLength(&trim_lists)); i++) {
        odd = odd != trim_piece_flips(f, trim_lists[record + 1u + i], q, hi);
    }
    return odd;
}

// The parity of the first `count` pieces of `f` crossed from `q` towards +u (a
// TRIM_KIND_ALL root: its corner is off the face and no piece reaches its edge).
fn trim_all_crossings(f: TrimFace, count: u32, q: vec2<f32>) -> bool {
    var odd = false;
    for (var k = 0u; k < min(count, arrayLength(&trim_piece_offsets)); k++) {
        odd = odd != trim_piece_flips(f, k, q, f.size);
    }
    return odd;
}

// What the tree says of the face-local cell `lo`..`hi` as a whole (`TrimBuffers::
// classify_cell` is its CPU twin): TRIM_CELL_OUT (no point of it on the face), TRIM_CELL_IN
// (every point on it), or TRIM_CELL_CROSSED (either, or not known without a finer look): the
// walk follows the cell down while one child holds it; at a constant leaf it knows, at
// another leaf it knows when none of the leaf's pieces meets the cell (their control points'
// box misses it: the boundary does not enter the cell, so its centre answers for all).
const TRIM_CELL_OUT: u32 = 0u;
const TRIM_CELL_IN: u32 = 1u;
const TRIM_CELL_CROSSED: u32 = 2u;

fn trim_cell(face: u32, cell_lo: vec2<f32>, cell_hi: vec2<f32>) -> u32 {
    let f = trim_faces[face];
    if any(cell_hi < vec2<f32>(0.0)) || any(cell_lo > f.size) {
        return TRIM_CELL_OUT;
    }
    if any(cell_lo < vec2<f32>(0.0)) || any(cell_hi > f.size) {
        return TRIM_CELL_CROSSED;
    }
    var lo = vec2<f32>(0.0);
    var hi = f.size;
    var index = f.nodes;
    for (var step = 0u; step < TRIM_MAX_STEPS; step++) {
        let word = trim_nodes[index];
        let kind = word >> 29u;
        let payload = word & TRIM_PAYLOAD;
        if kind == TRIM_KIND_CONSTANT {
            return select(TRIM_CELL_OUT, TRIM_CELL_IN, payload != 0u);
        }
        if kind != TRIM_KIND_SPLIT {
            var meets = false;
            if kind == TRIM_KIND_ONE {
                meets = trim_piece_meets(f, payload, cell_lo, cell_hi);
            } else if kind == TRIM_KIND_TWO {
                meets = trim_piece_meets(f, bitcast<u32>(trim_floats[payload + 3u]), cell_lo, cell_hi)
                    || trim_piece_meets(f, bitcast<u32>(trim_floats[payload + 4u]), cell_lo, cell_hi);
            } else if kind == TRIM_KIND_ALL {
                for (var k = 0u; k < min(payload, arrayLength(&trim_piece_offsets)); k++) {
                    meets = meets || trim_piece_meets(f, k, cell_lo, cell_hi);
                }
            } else {
                let count = trim_lists[payload] & ~TRIM_LIST_CORNER;
                for (var i = 0u; i < min(count, arrayLength(&trim_lists)); i++) {
                    meets = meets || trim_piece_meets(f, trim_lists[payload + 1u + i], cell_lo, cell_hi);
                }
            }
            if meets {
                return TRIM_CELL_CROSSED;
            }
            let inside = trim_classify(face, 0.5 * (cell_lo + cell_hi));
            return select(TRIM_CELL_OUT, TRIM_CELL_IN, inside);
        }
        let mid = 0.5 * (lo + hi);
        let right = cell_lo >= mid;
        let left = cell_hi <= mid;
        if !all(right | left) {
            return TRIM_CELL_CROSSED;
        }
        index = f.nodes + (word & TRIM_PAYLOAD) + select(0u, 1u, right.x) + select(0u, 2u, right.y);
        lo = select(lo, mid, right);
        hi = select(mid, hi, right);
    }
    return TRIM_CELL_CROSSED;
}

// Whether piece `k` of `f` may meet the cell `lo`..`hi`: its control triangle does (no
// separating axis among the box's two and the triangle's three edge normals).
fn trim_piece_meets(f: TrimFace, k: u32, lo: vec2<f32>, hi: vec2<f32>) -> bool {
    let piece = trim_piece(f, k);
    let c0 = piece.c0;
    let c1 = piece.c1;
    let c2 = piece.c2;
    let box_lo = min(c0, min(c1, c2));
    let box_hi = max(c0, max(c1, c2));
    var meets = all(box_lo <= hi) & all(box_hi >= lo);
    let centre = 0.5 * (lo + hi);
    let half = 0.5 * (hi - lo);
    let edges = array<vec2<f32>, 3>(c1 - c0, c2 - c1, c0 - c2);
    for (var e = 0u; e < 3u; e++) {
        let n = vec2<f32>(-edges[e].y, edges[e].x);
        let p = vec3<f32>(dot(n, c0), dot(n, c1), dot(n, c2));
        let r = abs(n.x) * half.x + abs(n.y) * half.y;
        let m = dot(n, centre);
        meets = meets & (min(p.x, min(p.y, p.z)) <= m + r) & (max(p.x, max(p.y, p.z)) >= m - r);
    }
    return meets;
}

// Whether the face-local point `q` lies on face `face`.
fn trim_classify(face: u32, q: vec2<f32>) -> bool {
    return trim_classify_within(face, q, vec2<f32>(0.0));
}

// `trim_classify` for a pixel whose footprint in (u, v) is `footprint`: the walk stops at the
// first cell no larger than it in both directions and answers by the cell's coverage bit
// (most of it on the face or not), so that a pixel covering many cells (a distant perforated
// face) takes their majority, not whichever one its centre falls in (moiré).
// `TrimBuffers::classify_within` is its CPU twin.
fn trim_classify_within(face: u32, q: vec2<f32>, footprint: vec2<f32>) -> bool {
    let f = trim_faces[face];
    if any(q < vec2<f32>(0.0)) || any(q > f.size) {
        return false;
    }
    var lo = vec2<f32>(0.0);
    var hi = f.size;
    var index = f.nodes;
    for (var step = 0u; step < TRIM_MAX_STEPS; step++) {
        let word = trim_nodes[index];
        let payload = word & TRIM_PAYLOAD;
        let kind = word >> 29u;
        if (kind == TRIM_KIND_SPLIT) & all(hi - lo <= footprint) {
            return (word & TRIM_COVERAGE) != 0u;
        }
        if kind == TRIM_KIND_SPLIT {
            let mid = 0.5 * (lo + hi);
            let right = q.x >= mid.x;
            let up = q.y >= mid.y;
            index = f.nodes + payload + select(0u, 1u, right) + select(0u, 2u, up);
            lo = select(lo, mid, vec2<bool>(right, up));
            hi = select(mid, hi, vec2<bool>(right, up));
            continue;
        }
        if kind == TRIM_KIND_CONSTANT {
            return payload != 0u;
        }
        if kind == TRIM_KIND_ONE {
            return trim_value(f, payload, q) >= 0.0;
        }
        if kind == TRIM_KIND_TWO {
            let positive = trim_floats[payload] * q.x + trim_floats[payload + 1u] * q.y
                >= trim_floats[payload + 2u];
            let k = bitcast<u32>(select(trim_floats[payload + 4u], trim_floats[payload + 3u], positive));
            return trim_value(f, k, q) >= 0.0;
        }
        if kind == TRIM_KIND_ALL {
            return trim_all_crossings(f, payload, q);
        }
        // Fallback: the corner's answer and the crossings within the cell.
        return ((trim_lists[payload] & TRIM_LIST_CORNER) != 0u) != trim_crossings(f, payload, q, hi);
    }
    return false;
}

// Piece `k` of `f` at `q`: its implicit value (either sign), that value's gradient in
// (u, v), and where along the piece `q` lies (0 at its start, 1 at its end: the Loop–Blinn
// x, or the projection on the chord), from `trim_value`'s form. `TrimBuffers::
// value_gradient` is the CPU twin.
struct TrimValueGradient {
    value: f32,
    gradient: vec2<f32>,
    along: f32,
}

fn trim_value_gradient(f: TrimFace, k: u32, q: vec2<f32>) -> TrimValueGradient {
    let piece = trim_piece(f, k);
    let c0 = piece.c0;
    let e1 = piece.c1 - c0;
    let e2 = piece.c2 - c0;
    let d = q - c0;
    if (piece.word & TRIM_PIECE_LINE) != 0u {
        let n = vec2<f32>(-e2.y, e2.x) / length(e2);
        return TrimValueGradient(dot(n, d), n, dot(d, e2) / dot(e2, e2));
    }
    let det = e1.x * e2.y - e1.y * e2.x;
    let ga = vec2<f32>(e2.y, -e2.x) / det;
    let gb = vec2<f32>(-e1.y, e1.x) / det;
    let beta = dot(gb, d);
    let x = 0.5 * dot(ga, d) + beta;
    let gx = 0.5 * ga + gb;
    return TrimValueGradient(x * x - beta, 2.0 * x * gx - gb, x);
}

// Piece `k`'s distance from `q` in pixels, when `q` lies within its box grown by `reach`
// (1e30 otherwise: an implicit form says nothing far from its piece): beside the piece,
// to first order (|F| / |∇F|, the gradient taken to the screen through the pixel's (u, v)
// steps `jx`, `jy`); past its ends, the distance to the end (the form there would measure
// to the parabola or the chord beyond the piece, which a neighbouring piece's end does not
// follow).
fn trim_piece_pixels(f: TrimFace, k: u32, q: vec2<f32>, jx: vec2<f32>, jy: vec2<f32>, reach: vec2<f32>) -> f32 {
    let piece = trim_piece(f, k);
    let lo = min(piece.c0, min(piece.c1, piece.c2)) - reach;
    let hi = max(piece.c0, max(piece.c1, piece.c2)) + reach;
    if any(q < lo) || any(q > hi) {
        return 1e30;
    }
    let vg = trim_value_gradient(f, k, q);
    if (vg.along < 0.0) || (vg.along > 1.0) {
        // (u, v) to pixels: the inverse of the steps' matrix.
        let end = select(piece.c2, piece.c0, vg.along < 0.0);
        let delta = q - end;
        let det = jx.x * jy.y - jx.y * jy.x;
        let pixels = vec2<f32>(jy.y * delta.x - jy.x * delta.y, jx.x * delta.y - jx.y * delta.x)
            / select(det, 1e-30, abs(det) < 1e-30);
        return length(pixels);
    }
    let g = vec2<f32>(dot(vg.gradient, jx), dot(vg.gradient, jy));
    return abs(vg.value) / max(length(g), 1e-30);
}

// The leaf word of face `f`'s tree at the face-local point `q` (clamped to the root).
fn trim_leaf_at(f: TrimFace, point: vec2<f32>) -> u32 {
    let q = clamp(point, vec2<f32>(0.0), f.size);
    var lo = vec2<f32>(0.0);
    var hi = f.size;
    var index = f.nodes;
    for (var step = 0u; step < TRIM_MAX_STEPS; step++) {
        let word = trim_nodes[index];
        if (word >> 29u) != TRIM_KIND_SPLIT {
            return word;
        }
        let mid = 0.5 * (lo + hi);
        let right = q.x >= mid.x;
        let up = q.y >= mid.y;
        index = f.nodes + (word & TRIM_PAYLOAD) + select(0u, 1u, right) + select(0u, 2u, up);
        lo = select(lo, mid, vec2<bool>(right, up));
        hi = select(mid, hi, vec2<bool>(right, up));
    }
    return TRIM_KIND_CONSTANT << 29u;
}

// The least distance in pixels from `q` to the pieces of the leaf `word` of `f` (those whose
// box, grown by `reach`, holds `q`; a one-piece leaf's piece whatever its box).
fn trim_leaf_pixels(f: TrimFace, word: u32, q: vec2<f32>, jx: vec2<f32>, jy: vec2<f32>, reach: vec2<f32>) -> f32 {
    let payload = word & TRIM_PAYLOAD;
    let kind = word >> 29u;
    var best = 1e30;
    if kind == TRIM_KIND_ONE {
        best = trim_piece_pixels(f, payload, q, jx, jy, vec2<f32>(1e30));
    } else if kind == TRIM_KIND_TWO {
        best = min(
            trim_piece_pixels(f, bitcast<u32>(trim_floats[payload + 3u]), q, jx, jy, reach),
            trim_piece_pixels(f, bitcast<u32>(trim_floats[payload + 4u]), q, jx, jy, reach),
        );
    } else if kind == TRIM_KIND_ALL {
        for (var k = 0u; k < min(payload, arrayLength(&trim_piece_offsets)); k++) {
            best = min(best, trim_piece_pixels(f, k, q, jx, jy, reach));
        }
    } else if kind == TRIM_KIND_FALLBACK {
        let count = trim_lists[payload] & ~TRIM_LIST_CORNER;
        for (var i = 0u; i < min(count, arrayLength(&trim_lists)); i++) {
            best = min(best, trim_piece_pixels(f, trim_lists[payload + 1u + i], q, jx, jy, reach));
        }
    }
    return best;
}

// How far, in pixels, the face-local point `q` of face `face` lies from the trim boundary
// near it, to first order: the least distance to the pieces of the leaves at the four
// corners of the pixel's (u, v) reach about `q` (a boundary within a pixel lies in one of
// them where the leaves are no smaller than the reach), 1e30 where none has a piece near.
// `jx`, `jy`: the (u, v) change over a pixel step in x and in y. The analytic coverage of a
// trimmed edge's pixels is 0.5 + this (`TrimBuffers::edge_pixels` is the CPU twin).
fn trim_edge_pixels(face: u32, q: vec2<f32>, jx: vec2<f32>, jy: vec2<f32>) -> f32 {
    let f = trim_faces[face];
    let reach = abs(jx) + abs(jy);
    var best = 1e30;
    var last = 0xffffffffu;
    for (var corner = 0u; corner < 4u; corner++) {
        let side = vec2<f32>(select(-1.0, 1.0, (corner & 1u) != 0u), select(-1.0, 1.0, (corner & 2u) != 0u));
        let word = trim_leaf_at(f, q + side * reach);
        // The same leaf as the corner before: nothing new (most pixels).
        if word != last {
            best = min(best, trim_leaf_pixels(f, word, q, jx, jy, reach));
        }
        last = word;
    }
    return best;
}
