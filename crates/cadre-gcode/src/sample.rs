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

/// The path of `moves` from the machine's origin, as runs; arcs sampled to `tolerance`
/// (mm, chord to arc).
pub fn sample_moves(moves: &[Move], tolerance: f64) -> Vec<PathRun> {
    let tolerance = if tolerance.is_finite() && tolerance > 0.0 {
        tolerance
    } else {
        1e-3
    };
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
                arc_points(at, end, centre, turns, axis, tolerance, |p| {
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

/// Calls `out` with the points after `start` along the arc to `end` about `centre` (its
/// turns signed about `axis`), the radius and the axial height going linearly from start to
/// end (a helix; a spiral where the program's radii differ).
fn arc_points(
    start: DVec3,
    end: DVec3,
    centre: DVec3,
    turns: f64,
    axis: Axis,
    tolerance: f64,
    mut out: impl FnMut(DVec3),
) {
    let (u, v, n) = match axis {
        Axis::Z => (0, 1, 2),
        Axis::Y => (2, 0, 1),
        Axis::X => (1, 2, 0),
    };
    let polar = |p: DVec3| {
        let (du, dv) = (p[u] - centre[u], p[v] - centre[v]);
        (du.hypot(dv), dv.atan2(du))
    };
    let (r0, a0) = polar(start);
    let (r1, _) = polar(end);
    let angle = turns * std::f64::consts::TAU;
    let r = r0.max(r1);
    let step = if r > tolerance {
        2.0 * (1.0 - tolerance / r).clamp(-1.0, 1.0).acos()
    } else {
        std::f64::consts::PI
    };
    let count = ((angle.abs() / step.max(std::f64::consts::TAU / MAX_PER_TURN)).ceil() as usize)
        .clamp(1, (MAX_PER_TURN * turns.abs().max(1.0)) as usize);
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
