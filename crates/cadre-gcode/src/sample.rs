//! Moves as polylines to draw: arcs and helices sampled so that no chord strays more than a
//! tolerance from the exact arc (the viewer passes what a pixel is worth at the current
//! zoom), consecutive moves of the same kind joined into one run.

use crate::{Axis, Move, MoveKind};
use glam::DVec3;

/// Consecutive moves drawn alike: rapids, or cutting moves (feeds and arcs).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PathRun {
    /// Rapids (else feeds and arcs).
    pub rapid: bool,
    /// Machine coordinates, mm: the first is where the run starts.
    pub points: Vec<DVec3>,
    /// For each segment (`points[k]` to `points[k + 1]`), the index of its move.
    pub moves: Vec<u32>,
}

/// Most chords one arc turn is sampled into, whatever the tolerance.
const MAX_PER_TURN: f64 = 4096.0;
/// Most chords one arc (a helix of many turns) is sampled into: a bound on memory whatever
/// the program asks (a helix of 10⁴ turns keeps 26 chords a turn).
const MAX_PER_ARC: f64 = 262_144.0;

/// Most points a path is sampled into in all (16 M, 400 MB of `DVec3`): past it the arcs'
/// tolerance is coarsened until they fit.
pub const MAX_PATH_POINTS: usize = 1 << 24;

/// The path of `moves` from the machine's origin, as runs; arcs sampled to `tolerance`
/// (mm, chord to arc), or coarser where that would take more than [`MAX_PATH_POINTS`].
pub fn sample_moves(moves: &[Move], tolerance: f64) -> Vec<PathRun> {
    let mut tolerance = if tolerance.is_finite() && tolerance > 0.0 {
        tolerance
    } else {
        1e-3
    };
    // The chords a tolerance takes, counted before anything is kept; an arc's count goes
    // as 1/√tolerance, so a few rounds of scaling bring it under the bound — unless arcs are
    // held at their cap (many turns at a fine tolerance): then the cap is shared out.
    let mut cap = MAX_PER_ARC;
    let count_at = |tolerance: f64, cap: f64| {
        let mut at = DVec3::ZERO;
        let (mut straight, mut arcs, mut count) = (0usize, 0usize, 0usize);
        for m in moves {
            let end = m.machine_end();
            match (m.centre, m.turns, m.axis) {
                (Some(centre), Some(turns), Some(axis)) => {
                    let centre = DVec3::from(centre) + DVec3::from(m.offset);
                    count += arc_chords((at, end, centre), turns, axis, (tolerance, cap));
                    arcs += 1;
                }
                _ => {
                    count += 1;
                    straight += 1;
                }
            }
            at = end;
        }
        (count, straight, arcs)
    };
    for _ in 0..8 {
        let (count, _, _) = count_at(tolerance, cap);
        if count <= MAX_PATH_POINTS {
            break;
        }
        let over = count as f64 / MAX_PATH_POINTS as f64;
        tolerance *= (over * 1.1).powi(2);
    }
    let (count, straight, arcs) = count_at(tolerance, cap);
    if count > MAX_PATH_POINTS && arcs > 0 {
        cap = (MAX_PATH_POINTS.saturating_sub(straight) / arcs).max(8) as f64;
    }
    let mut runs: Vec<PathRun> = Vec::new();
    let mut at = DVec3::ZERO;
    for (index, m) in moves.iter().enumerate() {
        let rapid = m.kind == MoveKind::Rapid;
        let end = m.machine_end();
        if runs.last().is_none_or(|r| r.rapid != rapid) {
            runs.push(PathRun {
                rapid,
                points: vec![at],
                moves: Vec::new(),
            });
        }
        let Some(run) = runs.last_mut() else { break };
        match (m.centre, m.turns, m.axis) {
            (Some(centre), Some(turns), Some(axis)) => {
                let centre = DVec3::from(centre) + DVec3::from(m.offset);
                arc_points((at, end, centre), turns, axis, (tolerance, cap), |p| {
                    run.points.push(p);
                    run.moves.push(index as u32);
                });
            }
            _ => {
                run.points.push(end);
                run.moves.push(index as u32);
            }
        }
        at = end;
    }
    runs
}

/// The (u, v, n) axis indices of an arc about `axis`.
fn plane_axes(axis: Axis) -> (usize, usize, usize) {
    match axis {
        Axis::Z => (0, 1, 2),
        Axis::Y => (2, 0, 1),
        Axis::X => (1, 2, 0),
    }
}

/// How many chords an arc takes at `tolerance`, at most `cap` ([`arc_points`]' count).
fn arc_chords(
    (start, end, centre): (DVec3, DVec3, DVec3),
    turns: f64,
    axis: Axis,
    (tolerance, cap): (f64, f64),
) -> usize {
    let (u, v, _) = plane_axes(axis);
    let radius = |p: DVec3| (p[u] - centre[u]).hypot(p[v] - centre[v]);
    let r = radius(start).max(radius(end));
    let angle = turns * std::f64::consts::TAU;
    let step = if r > tolerance {
        2.0 * (1.0 - tolerance / r).clamp(-1.0, 1.0).acos()
    } else {
        std::f64::consts::PI
    };
    (angle.abs() / step.max(std::f64::consts::TAU / MAX_PER_TURN))
        .ceil()
        .clamp(1.0, cap.max(1.0)) as usize
}

/// Calls `out` with the points after `start` along the arc to `end` about `centre` (its
/// turns signed about `axis`), the radius and the axial height going linearly from start to
/// end (a helix; a spiral where the program's radii differ).
fn arc_points(
    (start, end, centre): (DVec3, DVec3, DVec3),
    turns: f64,
    axis: Axis,
    limits: (f64, f64),
    mut out: impl FnMut(DVec3),
) {
    let (u, v, n) = plane_axes(axis);
    let polar = |p: DVec3| {
        let (du, dv) = (p[u] - centre[u], p[v] - centre[v]);
        (du.hypot(dv), dv.atan2(du))
    };
    let (r0, a0) = polar(start);
    let (r1, _) = polar(end);
    let angle = turns * std::f64::consts::TAU;
    let count = arc_chords((start, end, centre), turns, axis, limits);
    for k in 1..=count {
        if k == count {
            out(end);
            break;
        }
        let f = k as f64 / count as f64;
        let a = a0 + angle * f;
        let radius = r0 + (r1 - r0) * f;
        let mut p = DVec3::ZERO;
        p[u] = centre[u] + radius * a.cos();
        p[v] = centre[v] + radius * a.sin();
        p[n] = start[n] + (end[n] - start[n]) * f;
        out(p);
    }
}
