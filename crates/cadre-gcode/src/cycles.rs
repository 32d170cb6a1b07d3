//! Canned cycles G81–G89 as RS-274/NGC runs them, in any plane (the cycle's axis is the
//! plane's normal: Z in G17): for each of the L repeats, a rapid to the hole (first up to the
//! R plane if below it), a rapid down to R, the cycle's own moves to the bottom and back, then
//! the retract to R (G99) or to the higher of R and where the axis was before (G98). Under
//! G91, R is relative to that position and the bottom to R, and X/Y step each repeat.

use crate::MoveKind;
use crate::machine::{Code, Machine, Words};
use glam::DVec3;

/// How far a peck backs off (G73) or stops short of the last depth (G83), mm (LinuxCNC's
/// 0.010 inch).
const PECK_CLEARANCE: f64 = 0.254;

/// Runs cycle `code` (730, 740, 810–890) for the block.
pub(crate) fn run(m: &mut Machine, line: u32, words: &Words, code: Code) -> Result<(), String> {
    let (u, v, n) = m.plane_axes();
    let letters = [b'x', b'y', b'z'];
    let unit = m.unit();
    let offset = m.offset();
    let Some(r) = m.cycle.r else {
        return Err(format!("G{} without R (the retract plane)", code / 10));
    };
    let Some(bottom) = m.cycle.z.or_else(|| words.get(letters[n])) else {
        return Err(format!(
            "G{} without {} (the hole's bottom)",
            code / 10,
            (letters[n] as char).to_ascii_uppercase()
        ));
    };
    let repeats = match words.get(b'l') {
        None => 1,
        Some(l) if l >= 0.0 && l.fract() == 0.0 && l <= 1e6 => l as u64,
        Some(l) => return Err(format!("L{l} is not a repeat count")),
    };
    let old = m.pos[n];
    // The R plane and the bottom along the cycle's axis, machine coordinates.
    let (r_level, bottom_level) = if m.absolute {
        (r * unit + offset[n], bottom * unit + offset[n])
    } else {
        let r_level = old + r * unit;
        (r_level, r_level + bottom * unit)
    };
    if bottom_level > r_level {
        m.warn(
            line,
            "the hole's bottom is above its R plane: drilled upwards",
        );
    }
    let clear = if m.retract_to_r {
        r_level
    } else {
        old.max(r_level)
    };
    let q = m.cycle.q.map(|q| q * unit);
    // Up to R first, if below it.
    if m.pos[n] < r_level {
        let mut to = m.pos;
        to[n] = r_level;
        m.emit(MoveKind::Rapid, line, to, None);
    }
    for k in 0..repeats {
        // The hole's position in the plane.
        let mut hole = m.pos;
        for axis in [u, v] {
            if let Some(value) = words.get(letters[axis]) {
                hole[axis] = if m.absolute {
                    value * unit + offset[axis]
                } else {
                    m.pos[axis] + value * unit
                };
            }
        }
        // (Absolute repeats drill the same hole again.)
        let _ = k;
        m.emit(MoveKind::Rapid, line, hole, None);
        let at = |level: f64| {
            let mut p = hole;
            p[n] = level;
            p
        };
        if m.pos[n] != r_level {
            m.emit(MoveKind::Rapid, line, at(r_level), None);
        }
        match code {
            830 | 730 => match q {
                Some(q) if q > 0.0 => peck(m, line, (r_level, bottom_level), q, code == 730, at),
                _ => {
                    m.warn(line, "a peck cycle without a positive Q: drilled in one go");
                    m.emit(MoveKind::Feed, line, at(bottom_level), None);
                }
            },
            _ => m.emit(MoveKind::Feed, line, at(bottom_level), None),
        }
        match code {
            // Out at the feed rate (tapping, boring).
            840 | 850 | 890 | 740 => m.emit(MoveKind::Feed, line, at(r_level), None),
            870 => {
                m.warn(line, "G87 back boring is drawn as a bore and feed out");
                m.emit(MoveKind::Feed, line, at(r_level), None);
            }
            _ => {}
        }
        m.emit(MoveKind::Rapid, line, at(clear), None);
    }
    Ok(())
}

/// G83 (full retract to R between pecks) or G73 (chip break: a small back-off) from R down
/// to the bottom in steps of `q`.
fn peck(
    m: &mut Machine,
    line: u32,
    (r_level, bottom): (f64, f64),
    q: f64,
    chip_break: bool,
    at: impl Fn(f64) -> DVec3,
) {
    let down = if bottom <= r_level { -1.0 } else { 1.0 };
    let mut depth = r_level;
    loop {
        let next = if down < 0.0 {
            (depth - q).max(bottom)
        } else {
            (depth + q).min(bottom)
        };
        m.emit(MoveKind::Feed, line, at(next), None);
        if next == bottom {
            break;
        }
        if chip_break {
            m.emit(
                MoveKind::Rapid,
                line,
                at(next - down * PECK_CLEARANCE),
                None,
            );
        } else {
            m.emit(MoveKind::Rapid, line, at(r_level), None);
            m.emit(
                MoveKind::Rapid,
                line,
                at(next - down * PECK_CLEARANCE),
                None,
            );
        }
        depth = next;
    }
}
