//! The interpreter on good and bad programs: every move's kind, end point (mm, program
//! coordinates), centre and turns worked out by hand from the RS-274/NGC rules, and the
//! warnings (with their lines) of what it does not run as written.

use cadre_gcode::{Axis, Limits, MoveKind, interpret, interpret_with, sample_moves};

fn close(a: [f64; 3], b: [f64; 3]) -> bool {
    a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-9)
}

#[track_caller]
fn assert_end(program: &cadre_gcode::Program, k: usize, end: [f64; 3]) {
    let got = program.moves[k].end;
    assert!(close(got, end), "move {k}: {got:?} vs {end:?}");
}

#[test]
fn straight_moves_units_and_distance_modes() {
    let p = interpret(
        "%\nN10 G21 G90 (mm, absolute)\nN20 G0 X10 Y5 Z2\nN30 G1 Z-1 F250\nN40 G91 X5\nG20 G90 X1\n G1 Y-0.5 ; inch\n%\nG0 X99 (after the end marker)\n",
    );
    assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    assert_eq!(p.moves.len(), 5);
    assert_eq!(p.moves[0].kind, MoveKind::Rapid);
    assert_eq!(p.moves[0].line, 3);
    assert_end(&p, 0, [10.0, 5.0, 2.0]);
    assert_end(&p, 1, [10.0, 5.0, -1.0]);
    assert_eq!(p.moves[1].feed, 250.0);
    assert_end(&p, 2, [15.0, 5.0, -1.0]);
    // G20: inches converted, the feed too; the modal G1 carries on.
    assert_end(&p, 3, [25.4, 5.0, -1.0]);
    assert_eq!(p.moves[3].kind, MoveKind::Feed);
    assert_end(&p, 4, [25.4, -12.7, -1.0]);
    assert_eq!(p.program_units, "inch");
    assert_eq!(p.units, "mm");
}

#[test]
fn arcs_by_centre_and_radius_in_every_plane() {
    let p = interpret(
        "G17 G0 X10 Y0\nG3 X-10 Y0 I-10 J0\nG2 X10 Y0 R10\nG2 X10 Y0 I-10\nG3 X0 Y10 R-10\nG3 X0 Y10 I0 J-10 Z5 P3\n",
    );
    assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    let arc = |k: usize| {
        let m = &p.moves[k];
        assert_eq!(m.kind, MoveKind::Arc);
        (m.centre.unwrap(), m.turns.unwrap(), m.axis.unwrap())
    };
    let (c, t, a) = arc(1);
    assert!(close(c, [0.0, 0.0, 0.0]) && (t - 0.5).abs() < 1e-12 && a == Axis::Z);
    // G2 from (−10, 0) to (10, 0) by R10: the clockwise half circle over the top.
    let (c, t, _) = arc(2);
    assert!(
        close(c, [0.0, 0.0, 0.0]) && (t + 0.5).abs() < 1e-9,
        "{c:?} {t}"
    );
    // A full circle: end = start.
    let (c, t, _) = arc(3);
    assert!(close(c, [0.0, 0.0, 0.0]) && (t + 1.0).abs() < 1e-12, "{t}");
    // R−10 asks for the long way round: 3/4 of a turn counter-clockwise, centre (10, 10).
    let (c, t, _) = arc(4);
    assert!(
        close(c, [10.0, 10.0, 0.0]) && (t - 0.75).abs() < 1e-9,
        "{c:?} {t}"
    );
    // A helix of 2¾ turns + P3: from (0, 10) about (0, 0) back... up 5.
    let (c, t, _) = arc(5);
    assert!(
        close(c, [0.0, 0.0, 0.0]) && (t - 3.0).abs() < 1e-9,
        "{c:?} {t}"
    );
    assert_end(&p, 5, [0.0, 10.0, 5.0]);

    // G18: the ZX plane, counter-clockwise seen from +Y takes Z towards X.
    let p = interpret("G18 G0 X0 Z10\nG3 X10 Z0 K-10\nG19 G0 Y0 Z10\nG2 Y10 Z0 K-10\n");
    assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    assert_eq!(p.moves[1].axis, Some(Axis::Y));
    assert!((p.moves[1].turns.unwrap() - 0.25).abs() < 1e-12);
    assert_eq!(p.moves[3].axis, Some(Axis::X));
    // In YZ, from +Z to +Y is clockwise seen from +X (positive rotation takes Y to Z).
    assert!((p.moves[3].turns.unwrap() + 0.25).abs() < 1e-12);

    // G90.1: the centre in absolute coordinates.
    let p = interpret("G0 X20 Y10\nG90.1 G3 X0 Y10 I10 J10\n");
    assert!(close(p.moves[1].centre.unwrap(), [10.0, 10.0, 0.0]));
}

#[test]
fn arcs_sample_within_the_tolerance() {
    let p = interpret("G0 X10 Y0\nG3 X10 Y0 I-10 J0 Z-3\n");
    let runs = sample_moves(&p.moves, 0.01);
    let cut = runs.iter().find(|r| !r.rapid).expect("the arc");
    let n = cut.points.len();
    // Sagitta 0.01 on radius 10: a chord of ≈ 5.1°, ≈ 71 chords a turn.
    assert!((60..90).contains(&n), "{n}");
    for w in cut.points.windows(2) {
        let mid = 0.5 * (w[0] + w[1]);
        let r = mid.truncate().length();
        assert!(10.0 - r <= 0.0101, "sagitta {}", 10.0 - r);
    }
    assert!((cut.points[n - 1] - glam::DVec3::new(10.0, 0.0, -3.0)).length() < 1e-12);
}

#[test]
fn work_offsets_g92_and_homes() {
    let p = interpret(
        "G10 L2 P2 X100 Y50\nG55 G0 X0 Y0\nG54 G0 X0 Y0\nG92 X5\nG0 X10\nG92.1\nG0 X10\nG28.1\nG0 X1 Y1 Z1\nG28 Z20\n",
    );
    assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    assert_end(&p, 0, [0.0, 0.0, 0.0]);
    assert!(close(p.moves[0].offset, [100.0, 50.0, 0.0]));
    assert!(close(
        p.moves[0].machine_end().to_array(),
        [100.0, 50.0, 0.0]
    ));
    assert!(close(p.moves[1].machine_end().to_array(), [0.0, 0.0, 0.0]));
    // G92 X5 at machine X0: program X10 is machine X5.
    assert!(close(p.moves[2].machine_end().to_array(), [5.0, 0.0, 0.0]));
    assert_end(&p, 2, [10.0, 0.0, 0.0]);
    assert!(close(p.moves[3].machine_end().to_array(), [10.0, 0.0, 0.0]));
    // G28.1 stored (10, 0, 0); G28 Z20: up to Z20, then Z home (0).
    assert_end(&p, 5, [1.0, 1.0, 20.0]);
    assert_end(&p, 6, [1.0, 1.0, 0.0]);
    assert_eq!(p.moves[6].kind, MoveKind::Rapid);
}

#[test]
fn canned_cycles_drill_peck_and_repeat() {
    // G81 at three holes, G99: back to R after each; then under G98 from Z10, back to 10.
    let p = interpret(
        "G0 X0 Y0 Z10\nG99 G81 X5 Y5 Z-3 R2 F100\nX15\nG0 Z10\nG98 G81 X25 Z-3 R2\nG80\nG0 X0\n",
    );
    assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    let ends: Vec<[f64; 3]> = p.moves.iter().map(|m| m.end).collect();
    let kinds: Vec<MoveKind> = p.moves.iter().map(|m| m.kind).collect();
    use MoveKind::{Feed, Rapid};
    assert_eq!(
        kinds,
        [
            Rapid, // to (0, 0, 10)
            Rapid, Rapid, Feed, Rapid, // hole 1: over it, down to R, drill, back to R
            Rapid, Feed, Rapid, // hole 2 (already at R)
            Rapid, // up to 10
            Rapid, Rapid, Feed, Rapid, // hole 3, G98: back to 10
            Rapid
        ]
    );
    assert!(close(ends[2], [5.0, 5.0, 2.0]));
    assert!(close(ends[3], [5.0, 5.0, -3.0]));
    assert!(close(ends[4], [5.0, 5.0, 2.0]));
    assert!(close(ends[12], [25.0, 5.0, 10.0]));

    // G83 pecks of 2 from R1 to −5: feeds to −1, −3, −5 with full retracts between.
    let p = interpret("G0 Z10\nG83 X0 Y0 Z-5 R1 Q2 F100\n");
    let feeds: Vec<f64> = p
        .moves
        .iter()
        .filter(|m| m.kind == MoveKind::Feed)
        .map(|m| m.end[2])
        .collect();
    assert_eq!(feeds, [-1.0, -3.0, -5.0]);

    // G91 with L3: three holes 10 apart, R relative to the start, Z to R.
    let p = interpret("G0 X0 Y0 Z5\nG91 G81 X10 Z-4 R-3 L3 F50\n");
    assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    let bottoms: Vec<[f64; 3]> = p
        .moves
        .iter()
        .filter(|m| m.kind == MoveKind::Feed)
        .map(|m| m.end)
        .collect();
    assert_eq!(
        bottoms,
        [[10.0, 0.0, -2.0], [20.0, 0.0, -2.0], [30.0, 0.0, -2.0]]
    );
}

#[test]
fn parameters_and_expressions() {
    let p = interpret(
        "#1 = 2\n#<depth> = [#1 * -1.5]\n#<_safe> = 5\nG0 X[#1 + 1] Z#<_safe>\nG1 Z#<depth> F[100 * 2]\nG1 X[ATAN[1]/[1]] Y[SQRT[16] + ABS[-1] + [7 MOD 4]] Z[2 ** 3]\n#2 = 3 #3 = #2\nG1 X#3 Y[[1 LT 2] + [2 EQ 2] + [0 OR 3]]\n",
    );
    assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    assert_end(&p, 0, [3.0, 0.0, 5.0]);
    assert_end(&p, 1, [3.0, 0.0, -3.0]);
    assert_eq!(p.moves[1].feed, 200.0);
    assert_end(&p, 2, [45.0, 8.0, 8.0]);
    // `#3 = #2` reads #2 before the line sets it: 0.
    assert_end(&p, 3, [0.0, 3.0, 8.0]);
}

#[test]
fn subroutines_conditionals_and_loops() {
    let p = interpret(
        "o<hole> sub\n  G0 X#1 Y#2\n  G1 Z-1\n  G0 Z1\n  o<hole> return [#1 * 10]\no<hole> endsub\n\
         o<hole> call [1] [2]\n\
         o<hole> call [3] [4]\n\
         #<n> = #<_value>\n\
         o10 if [#<n> GT 100]\n  G0 X100\no10 elseif [#<n> EQ 30]\n  G0 X30\no10 else\n  G0 X-1\no10 endif\n\
         #1 = 0\no20 while [#1 LT 3]\n  G1 Y#1\n  #1 = [#1 + 1]\no20 endwhile\n\
         o30 do\n  #1 = [#1 - 1]\n  o30 if [#1 EQ 1]\n    o30 continue\n  o30 endif\n  G1 X#1\no30 while [#1 GT 0]\n\
         o40 repeat [4]\n  G1 Z[#1]\n  #1 = [#1 + 1]\n  o41 if [#1 EQ 3]\n    o40 break\n  o41 endif\no40 endrepeat\n\
         G0 Z50\nM30\nG0 Z99\n",
    );
    assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    let ends: Vec<[f64; 3]> = p.moves.iter().map(|m| m.end).collect();
    let expected: Vec<[f64; 3]> = vec![
        [1.0, 2.0, 0.0],
        [1.0, 2.0, -1.0],
        [1.0, 2.0, 1.0],
        [3.0, 4.0, 1.0],
        [3.0, 4.0, -1.0],
        [3.0, 4.0, 1.0],
        [30.0, 4.0, 1.0], // the return value 30
        [30.0, 0.0, 1.0], // while: Y0, Y1, Y2
        [30.0, 1.0, 1.0],
        [30.0, 2.0, 1.0],
        [2.0, 2.0, 1.0], // do: #1 3 → 2 (drawn), 1 (continue), 0 (drawn)
        [0.0, 2.0, 1.0],
        [0.0, 2.0, 0.0], // repeat: Z0, Z1, Z2, then break at #1 = 3
        [0.0, 2.0, 1.0],
        [0.0, 2.0, 2.0],
        [0.0, 2.0, 50.0],
    ];
    assert_eq!(ends, expected);
}

#[test]
fn bad_programs_warn_with_their_line_and_the_rest_loads() {
    let p = interpret(
        "G0 X1\nG1 X[1 +\nG1 X#<nope>\nG41 D1 G1 X2\nG5.2 X3 Y3 P1 L3\nG1 X[1/0]\nG2 X5\nG7.5 X6\nM98 P100\no99 call\nG1 X7 X8\nA10 G1 X9\nG1 X10 F100\n",
    );
    let lines: Vec<u32> = p.warnings.iter().map(|w| w.line).collect();
    for w in &p.warnings {
        eprintln!("line {}: {}", w.line, w.message);
    }
    for line in [2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12] {
        assert!(
            lines.contains(&line),
            "no warning for line {line}: {lines:?}"
        );
    }
    // What was valid still moved: lines 1, 4 (without compensation), 5 (as a straight
    // feed), 8 (G7.5 ignored, X6 kept under G5.2's… modal feed), 12, 13.
    let last = p.moves.last().expect("moves");
    assert_eq!(last.line, 13);
    assert_eq!(last.end, [10.0, 3.0, 0.0]);
    assert!(p.moves.iter().any(|m| m.line == 4 && m.end[0] == 2.0));
}

#[test]
fn endless_loops_and_deep_recursion_are_bounded() {
    let limits = Limits {
        max_blocks: 10_000,
        ..Limits::default()
    };
    let p = interpret_with("o1 while [1]\nG1 X1\nG1 X0\no1 endwhile\n", &limits);
    assert!(p.moves.len() <= 10_000);
    assert!(
        p.warnings.iter().any(|w| w.message.contains("stopped")),
        "{:?}",
        p.warnings
    );
    let p = interpret("o1 sub\no1 call\no1 endsub\no1 call\nG0 X1\n");
    assert!(
        p.warnings.iter().any(|w| w.message.contains("nested")),
        "{:?}",
        p.warnings
    );
    // Unclosed constructs are warned, not run off the end.
    let p = interpret("o1 if [0]\nG0 X1\n");
    assert!(!p.warnings.is_empty());
    let p = interpret("o2 while [0]\nG0 X1\n");
    assert!(!p.warnings.is_empty());
}

#[test]
fn splines_are_feeds_on_the_curve() {
    // G5.1 from (0, 0) to (10, 0) about the control point (5, 5): the quadratic's top is
    // (5, 2.5); G5 cubics, the second going on tangentially without I/J.
    let p = interpret(
        "G0 X0 Y0\nG5.1 X10 Y0 I5 J5 F100\nG5 X20 Y0 I2 J2 P-2 Q2\nG5 X30 Y0 P-2 Q-2\nG18 G5 X40 I1 J1 P1 Q1\n",
    );
    let on = |line: u32| -> Vec<[f64; 3]> {
        p.moves
            .iter()
            .filter(|m| m.line == line)
            .map(|m| {
                assert_eq!(m.kind, MoveKind::Feed);
                m.end
            })
            .collect()
    };
    let quadratic = on(2);
    assert!(quadratic.len() > 20, "{}", quadratic.len());
    assert_eq!(*quadratic.last().unwrap(), [10.0, 0.0, 0.0]);
    let top = quadratic.iter().map(|e| e[1]).fold(0.0, f64::max);
    assert!((top - 2.5).abs() < 2e-3, "{top}");
    for e in &quadratic {
        // On the parabola y = x (10 − x) / 10 · … : for control (5, 5), y = x − x²/10.
        let y = e[0] - e[0] * e[0] / 10.0;
        assert!((e[1] - y).abs() < 1e-9, "{e:?}");
    }
    let first = on(3);
    assert_eq!(*first.last().unwrap(), [20.0, 0.0, 0.0]);
    // The continuation leaves (20, 0) along the mirror of (18, 2): towards (22, −2), so it
    // first dips below the axis.
    let second = on(4);
    assert!(second[0][1] < 0.0, "{:?}", second[0]);
    assert_eq!(*second.last().unwrap(), [30.0, 0.0, 0.0]);
    // Outside G17: refused with a warning naming the line.
    assert!(on(5).is_empty());
    assert!(p.warnings.iter().any(|w| w.line == 5), "{:?}", p.warnings);
    assert_eq!(p.warnings.len(), 1, "{:?}", p.warnings);
}

#[test]
fn huge_helices_stay_bounded_when_sampled() {
    // P past 10,000 turns is refused with a warning; a hundred helices of 10,000 turns at a
    // nanometre would take 10¹¹ chords: the tolerance is coarsened to the bound instead.
    let p = interpret(
        "G0 X10\nG3 X10 I-10 P99999999\no1 repeat [100]\nG3 X10 I-10 Z-1 P10000\no1 endrepeat\n",
    );
    assert!(p.warnings.iter().any(|w| w.line == 2), "{:?}", p.warnings);
    assert_eq!(p.moves.len(), 102);
    let runs = sample_moves(&p.moves, 1e-9);
    let points: usize = runs.iter().map(|r| r.points.len()).sum();
    assert!(
        points <= cadre_gcode::MAX_PATH_POINTS + runs.len() && points > 1_000_000,
        "{points}"
    );
}

#[test]
fn the_json_has_the_documented_shape() {
    let p = interpret("G0 X1\nG3 X-1 I-1 J0\n");
    let json: serde_json::Value = serde_json::to_value(&p).expect("serialises");
    assert_eq!(json["units"], "mm");
    assert_eq!(json["moves"][0]["kind"], "rapid");
    assert_eq!(json["moves"][0]["line"], 1);
    assert_eq!(json["moves"][1]["kind"], "arc");
    assert_eq!(json["moves"][1]["turns"], 0.5);
    assert_eq!(
        json["moves"][1]["centre"],
        serde_json::json!([0.0, 0.0, 0.0])
    );
    assert!(json["moves"][0].get("centre").is_none());
    assert!(json["warnings"].as_array().unwrap().is_empty());
}

mod properties {
    use proptest::prelude::*;

    proptest! {
        /// Anything at all: no panic, every warning names a line of the text (or 0 for the
        /// count of those not listed).
        #[test]
        fn any_text_interprets_without_panicking(text in ".{0,400}") {
            let p = cadre_gcode::interpret(&text);
            let lines = text.lines().count() as u32;
            for w in &p.warnings {
                prop_assert!(w.line <= lines.max(1));
            }
        }

        /// G-code-shaped text built from the language's pieces.
        #[test]
        fn gcode_shaped_text_interprets_without_panicking(
            pieces in proptest::collection::vec(
                prop_oneof![
                    Just("G0"), Just("G1"), Just("G2"), Just("G3"), Just("G81"), Just("G83"),
                    Just("G91"), Just("G90"), Just("G20"), Just("X"), Just("Y"), Just("Z"),
                    Just("R"), Just("I"), Just("J"), Just("Q"), Just("L"), Just("P"),
                    Just("1"), Just("-2.5"), Just("[#1+1]"), Just("#1=3"), Just("\n"),
                    Just("o1 while [#1 LT 5]"), Just("o1 endwhile"), Just("#1=[#1+1]"),
                    Just("o2 sub"), Just("o2 endsub"), Just("o2 call [1]"), Just("("), Just(")"),
                ],
                0..60,
            )
        ) {
            let text = pieces.join(" ");
            let p = cadre_gcode::interpret_with(&text, &cadre_gcode::Limits {
                max_blocks: 100_000,
                ..Default::default()
            });
            for m in &p.moves {
                prop_assert!(m.end.iter().all(|v| v.is_finite()));
            }
            let _ = cadre_gcode::sample_moves(&p.moves, 0.01);
        }
    }
}
