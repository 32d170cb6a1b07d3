//! The trim quadtree classifies (u, v) points as the exact loops do: random star polygons
//! (corners, concave and convex) with round holes, stretched anisotropically, fitted under
//! anisotropic tolerances, queried at random points farther than a few tolerances from the
//! exact boundary; the oracle is the even-odd rule on a dense polygon of the exact curves.
//! Negative control: the tree of the same face without its first hole is caught disagreeing
//! at that hole's centre.

mod common;

use cadre_trim::layout::{KIND_CONSTANT, PAYLOAD, PIECE_LINE, PIECE_NEGATIVE, PIECE_OFFSET};
use cadre_trim::quadtree::{Leaf, Node};
use cadre_trim::quadtree::{grid_size, grid_step};
use cadre_trim::{CellClass, QuadPiece, TrimBuffers, TrimTree, Uv, UvTolerance, fit_points};
use common::{even_odd, to_boundary};
use proptest::prelude::*;
use std::f64::consts::TAU;

/// A face: its exact boundary as dense closed polylines (outer counter-clockwise, holes
/// clockwise) and, per loop, its smooth runs (a polygon's sides, a circle's quarters).
struct Face {
    loops: Vec<Vec<Uv>>,
    runs: Vec<Vec<Uv>>,
    holes: Vec<Uv>,
}

fn face(radii: &[f64], (angle, holes): (f64, &[f64]), stretch: Uv) -> Face {
    let n = radii.len();
    let corner = |k: usize| {
        let a = TAU * (k % n) as f64 / n as f64;
        stretch * (radii[k % n] * Uv::new(a.cos(), a.sin()))
    };
    let mut runs = Vec::new();
    let mut outer = Vec::new();
    for k in 0..n {
        let (a, b) = (corner(k), corner(k + 1));
        let side: Vec<Uv> = (0..=64).map(|i| a.lerp(b, f64::from(i) / 64.0)).collect();
        outer.extend_from_slice(&side[..64]);
        runs.push(side);
    }
    let mut loops = vec![outer];
    let mut centres = Vec::new();
    for (k, &radius) in holes.iter().enumerate() {
        // Holes on a ring, 120° apart (they do not meet), clockwise.
        let a = angle + TAU * k as f64 / 3.0;
        let centre = 0.12 * Uv::new(a.cos(), a.sin());
        let point = |t: f64| stretch * (centre + radius * Uv::new(t.cos(), -t.sin()));
        let mut hole = Vec::new();
        for q in 0..4 {
            let run: Vec<Uv> = (0..=200)
                .map(|i| point(TAU * (f64::from(q) + f64::from(i) / 200.0) / 4.0))
                .collect();
            hole.extend_from_slice(&run[..200]);
            runs.push(run);
        }
        loops.push(hole);
        centres.push(stretch * centre);
    }
    Face {
        loops,
        runs,
        holes: centres,
    }
}

fn pieces(face: &Face, tol: UvTolerance) -> Vec<QuadPiece> {
    face.runs.iter().flat_map(|r| fit_points(r, tol)).collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// A cell the packed tree calls in (out) has every one of its points on (off) the face
    /// by the point classifier; cells of every size are asked (random ones and the aligned
    /// depth-4 grid), and some get an answer.
    #[test]
    fn a_cell_called_in_or_out_is_so_at_every_point(
        radii in prop::collection::vec(0.35..1.0f64, 3..12),
        angle in 0.0..TAU,
        holes in prop::collection::vec(0.02..0.06f64, 0..3),
        cells in prop::collection::vec((0.0..1.0f64, 0.0..1.0f64, 1..7u32), 200),
    ) {
        let tol = UvTolerance { u: 1e-4, v: 1e-4 };
        let f = face(&radii, (angle, &holes), Uv::ONE);
        let mut buffers = TrimBuffers::default();
        let at = buffers.push(&TrimTree::build(&pieces(&f, tol))).unwrap();
        let record = buffers.faces[at];
        let size = [f64::from(record.size[0]), f64::from(record.size[1])];
        let mut known = 0;
        // The random cells, then every cell of the depth-4 grid (aligned with the tree's).
        let grid = (0..16u32).flat_map(|i| {
            (0..16u32).map(move |j| (f64::from(i) / 15.0, f64::from(j) / 15.0, 4u32))
        });
        for (x, y, depth) in cells.into_iter().chain(grid) {
            // A cell of 1/2^depth of the box, anywhere (not aligned with the tree's).
            let w = [size[0] / f64::from(1u32 << depth), size[1] / f64::from(1u32 << depth)];
            let lo = [x * (size[0] - w[0]), y * (size[1] - w[1])];
            let hi = [lo[0] + w[0], lo[1] + w[1]];
            let class = buffers.classify_cell(
                at,
                [lo[0] as f32, lo[1] as f32],
                [hi[0] as f32, hi[1] as f32],
            );
            if class == CellClass::Crossed {
                continue;
            }
            known += 1;
            for i in 0..=6 {
                for j in 0..=6 {
                    let p = record.origin
                        + Uv::new(
                            lo[0] + w[0] * f64::from(i) / 6.0,
                            lo[1] + w[1] * f64::from(j) / 6.0,
                        );
                    prop_assert_eq!(
                        buffers.classify(at, p),
                        class == CellClass::In,
                        "{:?} cell {:?}..{:?} at {}", class, lo, hi, p
                    );
                }
            }
        }
        prop_assert!(known > 0, "no cell was known");
        // Negative control: the whole box crosses the boundary.
        prop_assert_eq!(
            buffers.classify_cell(at, [0.0; 2], record.size),
            CellClass::Crossed
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn the_tree_classifies_as_the_exact_loops(
        radii in prop::collection::vec(0.35..1.0f64, 3..12),
        angle in 0.0..TAU,
        holes in prop::collection::vec(0.02..0.06f64, 0..3),
        stretch in (0.3..8.0f64, 0.1..3.0f64),
        tol_exp in (-5.0..-3.0f64, -5.0..-3.0f64),
        queries in prop::collection::vec((0.0..1.0f64, 0.0..1.0f64), 300),
        grid in any::<bool>(),
    ) {
        let stretch = Uv::new(stretch.0, stretch.1);
        let tol = UvTolerance {
            u: stretch.x * 10f64.powf(tol_exp.0),
            v: stretch.y * 10f64.powf(tol_exp.1),
        };
        let f = face(&radii, (angle, &holes), stretch);
        // Half the faces with their points on the grid where its step is within the
        // tolerance (they then move by up to a tolerance: the points checked are 4 away).
        let tree = TrimTree::build_on_grid(&pieces(&f, tol), grid.then_some(tol));
        let size = grid_size(tree.bounds);
        let fine = f64::from(grid_step(size[0])) <= tol.u && f64::from(grid_step(size[1])) <= tol.v;
        prop_assert_eq!(tree.on_grid, grid && fine);
        // Packed after another face, so that its records start past 0.
        let mut buffers = TrimBuffers::default();
        buffers.push(&TrimTree::build(&pieces(&face(&[0.5; 4], (0.0, &[]), Uv::ONE), tol))).unwrap();
        let at = buffers.push(&tree).unwrap();
        let (lo, hi) = tree.bounds;
        let mut checked = 0;
        let mut points = Vec::new();
        for (x, y) in queries {
            let p = lo + Uv::new(x, y) * (hi - lo) * 1.1 - 0.05 * (hi - lo);
            if to_boundary(&f.loops, p, Uv::new(tol.u, tol.v)) < 4.0 {
                continue;
            }
            checked += 1;
            points.push(p);
            prop_assert_eq!(tree.classify(p), even_odd(&f.loops, p), "at {}", p);
            prop_assert_eq!(buffers.classify(at, p), tree.classify(p), "packed, at {}", p);
        }
        prop_assert!(checked > 100, "only {} points away from the boundary", checked);
        for centre in &f.holes {
            prop_assert!(!tree.classify(*centre), "a hole's centre is on the face");
            prop_assert!(!buffers.classify(at, *centre), "packed: a hole's centre is on the face");
        }
        // Negative control of the packed words: with every constant leaf turned over and
        // every piece's form negated, the checked points inside the tree's box land on the
        // other side (the words are what decides).
        let mut flipped = buffers.clone();
        let first = flipped.faces[at].nodes as usize;
        for word in &mut flipped.nodes[first..] {
            if *word >> 29 == KIND_CONSTANT {
                *word ^= 1 & PAYLOAD;
            }
        }
        let record = flipped.faces[at];
        for k in record.pieces..record.pieces + record.piece_count {
            flipped.piece_offsets[k as usize] ^= PIECE_NEGATIVE;
        }
        let inside_box = |p: &&Uv| p.x > lo.x && p.y > lo.y && p.x < hi.x && p.y < hi.y;
        let all_root = matches!(tree.nodes[0], Node::Leaf { leaf: Leaf::All, .. });
        let forms_only = tree.fallback_leaves() == 0 && !all_root;
        let inside: Vec<&Uv> = points.iter().filter(inside_box).collect();
        let kept = inside.iter().filter(|p| flipped.classify(at, ***p) == tree.classify(***p)).count();
        // Fallback leaves and a whole-face root read control points, which the flip leaves
        // alone.
        if forms_only {
            prop_assert_eq!(kept, 0, "{} of {} answers survived the flip", kept, inside.len());
        }
        // Their negative control: with this face's points moved off its box, no crossing
        // is counted and the points on the face are lost.
        let mut moved = buffers.clone();
        let offsets = &buffers.piece_offsets[record.pieces as usize..(record.pieces + record.piece_count) as usize];
        let first_float = (offsets[0] & PIECE_OFFSET) as usize;
        // A point is a word on the grid, two floats off it.
        let point_words = if tree.on_grid { 1 } else { 2 };
        let end = offsets
            .iter()
            .map(|w| (w & PIECE_OFFSET) as usize + point_words * if w & PIECE_LINE != 0 { 2 } else { 3 })
            .max()
            .unwrap_or(first_float);
        let size = record.size;
        for (k, x) in moved.floats[first_float..end].iter_mut().enumerate() {
            if tree.on_grid {
                // Every point to the grid's last corner: no piece is crossed.
                *x = f32::from_bits(u32::MAX);
            } else {
                *x += 4.0 * size[k % 2];
            }
        }
        let on: Vec<&&Uv> = inside.iter().filter(|p| tree.classify(***p)).collect();
        let lost = on.iter().filter(|p| !moved.classify(at, ****p)).count();
        prop_assert!(on.is_empty() || lost > 0, "moving the pieces changed none of {} answers", on.len());
        // Negative control: without its first hole, the tree puts that hole's centre on
        // the face.
        if !f.holes.is_empty() {
            let without = Face {
                loops: vec![f.loops[0].clone()],
                runs: f.runs[..radii.len()].to_vec(),
                holes: Vec::new(),
            };
            let wrong = TrimTree::build(&pieces(&without, tol));
            prop_assert!(wrong.classify(f.holes[0]) != even_odd(&f.loops, f.holes[0]));
        }
        // The depth cap's fallback stays a small share of the leaves (where a tiny monotone
        // part meets its neighbours in a deep cell).
        prop_assert!(
            tree.capped_leaves() * 8 <= tree.nodes.len(),
            "{} leaves at the depth cap of {} nodes",
            tree.capped_leaves(),
            tree.nodes.len()
        );
    }
}

/// The distance from `p` to the polylines `loops` in pixels, where `inv` takes a (u, v)
/// displacement to pixels, and the distance to their nearest vertex.
fn pixels_to_loops(loops: &[Vec<Uv>], p: Uv, inv: glam::DMat2) -> (f64, f64) {
    let (mut best, mut corner) = (f64::INFINITY, f64::INFINITY);
    for l in loops {
        for k in 0..l.len() {
            let (a, b) = (inv * (l[k] - p), inv * (l[(k + 1) % l.len()] - p));
            let ab = b - a;
            let t = (-a.dot(ab) / ab.length_squared().max(1e-300)).clamp(0.0, 1.0);
            best = best.min((a + t * ab).length());
        }
    }
    // The polygon's own corners (the sides' ends), where a first-order estimate sees the
    // side's line and not its end.
    for l in loops.iter().take(1) {
        for q in l.iter().step_by(64) {
            corner = corner.min((inv * (*q - p)).length());
        }
    }
    (best, corner)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// The trim boundary's distance in pixels (`TrimBuffers::edge_pixels`, what the analytic
    /// coverage of a trimmed edge's pixels is made of) is the exact one within 0.1 px, for
    /// pixels up to 0.9 px from the boundary (past 0.5 px a pixel is wholly covered) where the
    /// trim curves turn no tighter than 10 px on screen (a first-order estimate is off by about
    /// d²/2R: a round hole 7 px across one way and 29 px the other turns within 2 px at its
    /// ends, and is off by a quarter pixel there) and 2 px from the outline's corners, with the
    /// pixel's (u, v) steps rotated and stretched. Negative control: steps twice too large.
    #[test]
    fn edge_distances_in_pixels_are_the_exact_ones(
        radii in prop::collection::vec(0.35..1.0f64, 3..12),
        angle in 0.0..TAU,
        holes in prop::collection::vec(0.02..0.06f64, 0..3),
        pixel in 0.0002..0.001f64,
        (stretch, turn) in (0.8..1.25f64, 0.0..TAU),
        queries in prop::collection::vec((0.0..1.0f64, 0.0..1.0f64), 4000),
    ) {
        let tol = UvTolerance { u: 1e-5, v: 1e-5 };
        let f = face(&radii, (angle, &holes), Uv::ONE);
        let tree = TrimTree::build(&pieces(&f, tol));
        let mut buffers = TrimBuffers::default();
        let at = buffers.push(&tree).unwrap();
        let (c, s) = (turn.cos(), turn.sin());
        let jx = pixel * stretch * Uv::new(c, s);
        let jy = pixel / stretch * Uv::new(-s, c);
        let inv = glam::DMat2::from_cols(jx, jy).inverse();
        let f32s = |v: Uv| [v.x as f32, v.y as f32];
        let (lo, hi) = tree.bounds;
        let (mut checked, mut control, mut off_twice) = (0, 0, 0);
        for (x, y) in queries {
            let p = lo + Uv::new(x, y) * (hi - lo);
            let (exact, corner) = pixels_to_loops(&f.loops, p, inv);
            if exact > 0.9 || corner < 2.0 {
                continue;
            }
            checked += 1;
            let got = f64::from(buffers.edge_pixels(at, p, f32s(jx), f32s(jy)));
            prop_assert!((got - exact).abs() <= 0.1, "{} px for {} px at {}", got, exact, p);
            // Halved by steps twice too large: off by more than 0.1 px from 0.4 px out.
            if exact >= 0.4 {
                control += 1;
                let twice = f64::from(buffers.edge_pixels(at, p, f32s(2.0 * jx), f32s(2.0 * jy)));
                off_twice += usize::from((twice - exact).abs() > 0.1);
            }
        }
        prop_assert_eq!(off_twice, control, "twice the steps: {} of {} still right ({} points checked)", control - off_twice, control, checked);
    }
}
