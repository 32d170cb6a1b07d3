//! The machine a block runs on: its modal state (units, distance modes, plane, motion,
//! coordinate system, feed, tool), its position, and a block's words run in RS-274/NGC's
//! order of execution (feed, tool, plane, units, coordinate system, distance modes, the
//! non-modal codes, then the motion, then the stops).

use crate::params::{Params, number};
use crate::{Axis, GcodeError, Limits, Move, MoveKind, Warning};
use glam::DVec3;

/// mm per inch.
const INCH: f64 = 25.4;
/// Most turns an arc's P may ask for.
const MAX_TURNS: f64 = 10_000.0;

/// A G or M code ×10 (G59.3 → 593), as the block holds it.
pub(crate) type Code = u32;

/// A block's words evaluated: its G and M codes, and every other letter's value (in the
/// program's units).
#[derive(Clone, Debug, Default)]
pub(crate) struct Words {
    pub g: Vec<Code>,
    pub m: Vec<Code>,
    /// By letter, `a` at 0 (`g`, `m`, `n`, `o` unused).
    pub values: [Option<f64>; 26],
}

impl Words {
    pub fn get(&self, letter: u8) -> Option<f64> {
        self.values[(letter - b'a') as usize]
    }

    fn has_g(&self, code: Code) -> bool {
        self.g.contains(&code)
    }

    fn has_axes(&self) -> bool {
        [b'x', b'y', b'z'].iter().any(|l| self.get(*l).is_some())
    }
}

/// Canned cycle words kept from one cycle block to the next.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct CycleWords {
    pub r: Option<f64>,
    pub z: Option<f64>,
    pub q: Option<f64>,
    pub p: Option<f64>,
}

/// The machine.
pub(crate) struct Machine {
    pub params: Params,
    /// Position, machine coordinates, mm.
    pub pos: DVec3,
    pub inch: bool,
    pub absolute: bool,
    pub arc_absolute: bool,
    /// The plane's normal (G17: Z).
    pub plane: Axis,
    /// The modal motion (0, 10, 20, 30, 381…, 800–890), `None` before any.
    pub motion: Option<Code>,
    /// G99 (retract to R) rather than G98.
    pub retract_to_r: bool,
    /// mm/min.
    pub feed: f64,
    pub tool: u32,
    pub selected_tool: u32,
    pub cycle: CycleWords,
    /// The last G5 spline's second control point (machine coordinates), for a next G5
    /// without I/J, which continues it tangentially.
    pub spline_tangent: Option<DVec3>,
    pub moves: Vec<Move>,
    pub warnings: Vec<Warning>,
    /// Warnings past the limit, counted.
    pub more_warnings: usize,
    pub limits: Limits,
    /// M2/M30 reached.
    pub ended: bool,
    /// The rotary axes were warned about once.
    warned_rotary: bool,
}

impl Machine {
    pub fn new(limits: &Limits) -> Machine {
        Machine {
            params: Params::default(),
            pos: DVec3::ZERO,
            inch: false,
            absolute: true,
            arc_absolute: false,
            plane: Axis::Z,
            motion: None,
            retract_to_r: false,
            feed: 0.0,
            tool: 0,
            selected_tool: 0,
            cycle: CycleWords::default(),
            spline_tangent: None,
            moves: Vec::new(),
            warnings: Vec::new(),
            more_warnings: 0,
            limits: *limits,
            ended: false,
            warned_rotary: false,
        }
    }

    /// Records a warning (counted past the limit).
    pub fn warn(&mut self, line: u32, message: impl Into<String>) {
        if self.warnings.len() < self.limits.max_warnings {
            self.warnings.push(Warning {
                line,
                message: message.into(),
            });
        } else {
            self.more_warnings += 1;
        }
    }

    /// mm per program unit.
    pub fn unit(&self) -> f64 {
        if self.inch { INCH } else { 1.0 }
    }

    /// The active coordinate system's offset plus the G92 offset, mm.
    pub fn offset(&self) -> DVec3 {
        self.work_offset() + self.g92_offset()
    }

    /// The active coordinate system's (G54–G59.3) offset, mm.
    fn work_offset(&self) -> DVec3 {
        let system = (self.params.get(number::COORDINATE_SYSTEM).round() as usize).clamp(1, 9);
        let base = number::G54 + 20 * (system - 1);
        DVec3::new(
            self.params.get(base),
            self.params.get(base + 1),
            self.params.get(base + 2),
        )
    }

    /// The G92 offset where it applies (else zero), mm.
    fn g92_offset(&self) -> DVec3 {
        if self.params.get(number::G92_ON) == 1.0 {
            DVec3::new(
                self.params.get(number::G92),
                self.params.get(number::G92 + 1),
                self.params.get(number::G92 + 2),
            )
        } else {
            DVec3::ZERO
        }
    }

    /// The position in program coordinates, mm.
    pub fn program_pos(&self) -> DVec3 {
        self.pos - self.offset()
    }

    /// Adds a move to `to` (machine coordinates); `false` once the move limit is reached.
    pub fn emit(&mut self, kind: MoveKind, line: u32, to: DVec3, arc: Option<(DVec3, f64)>) {
        if self.moves.len() >= self.limits.max_moves {
            return;
        }
        let offset = self.offset();
        self.moves.push(Move {
            kind,
            line,
            end: (to - offset).to_array(),
            centre: arc.map(|(c, _)| (c - offset).to_array()),
            turns: arc.map(|(_, t)| t),
            axis: arc.map(|_| self.plane),
            feed: if kind == MoveKind::Rapid {
                0.0
            } else {
                self.feed
            },
            tool: self.tool,
            offset: offset.to_array(),
        });
        self.pos = to;
    }

    /// The block's axis words as a target in machine coordinates: absolute or incremental
    /// per the distance mode, in program coordinates offset to the machine.
    pub fn target(&self, words: &Words) -> DVec3 {
        let mut p = self.program_pos();
        let unit = self.unit();
        for (i, letter) in [b'x', b'y', b'z'].into_iter().enumerate() {
            if let Some(v) = words.get(letter) {
                p[i] = if self.absolute {
                    v * unit
                } else {
                    p[i] + v * unit
                };
            }
        }
        p + self.offset()
    }

    /// The (u, v, n) axis indices of the plane: positive rotation about n takes u to v.
    pub fn plane_axes(&self) -> (usize, usize, usize) {
        match self.plane {
            Axis::Z => (0, 1, 2),
            Axis::Y => (2, 0, 1),
            Axis::X => (1, 2, 0),
        }
    }

    /// Runs one block (its words already evaluated).
    pub fn run_block(&mut self, line: u32, words: &Words) -> Result<(), GcodeError> {
        let err = |message: String| GcodeError::Run { line, message };
        // Rotary and secondary axes are not drawn.
        if !self.warned_rotary
            && [b'a', b'b', b'c', b'u', b'v', b'w']
                .iter()
                .any(|l| words.get(*l).is_some())
        {
            self.warned_rotary = true;
            self.warn(
                line,
                "rotary and secondary axes (A, B, C, U, V, W) are not drawn: the path shows X, Y and Z only",
            );
        }
        // Motion codes (group 1) and non-modal codes (group 0) that take the axis words.
        let motions: Vec<Code> = words.g.iter().copied().filter(|g| is_motion(*g)).collect();
        if motions.len() > 1 {
            self.warn(
                line,
                format!(
                    "two motion codes on one line ({}): the last is used",
                    codes(&motions, 'G')
                ),
            );
        }
        for g in &words.g {
            if !is_known_g(*g) {
                self.warn(line, format!("G{} is not supported: ignored", show(*g)));
            }
        }
        for m in &words.m {
            match m {
                0
                | 10
                | 20
                | 300
                | 600
                | 30
                | 40
                | 50
                | 60
                | 70
                | 80
                | 90
                | 480
                | 490
                | 500
                | 510
                | 520
                | 530
                | 610
                | 620..=680
                | 700..=730
                | 1000..=1990 => {}
                980 | 990 => self.warn(
                    line,
                    format!(
                        "M{} (Fanuc subprograms) is not supported: ignored",
                        show(*m)
                    ),
                ),
                _ => self.warn(line, format!("M{} is not supported: ignored", show(*m))),
            }
        }
        // Feed mode, feed, tool.
        if words.has_g(930) {
            self.warn(
                line,
                "G93 inverse-time feed: F values are kept as read, not as mm/min",
            );
        }
        if let Some(f) = words.get(b'f') {
            self.feed = f * self.unit();
        }
        if let Some(t) = words.get(b't') {
            if t < 0.0 || t.fract() != 0.0 || t > f64::from(u32::MAX) {
                self.warn(line, format!("T{t} is not a tool number: ignored"));
            } else {
                self.selected_tool = t as u32;
            }
        }
        if words.m.contains(&60) {
            self.tool = self.selected_tool;
            self.params.set(number::TOOL, f64::from(self.tool));
        }
        if words.m.contains(&610)
            && let Some(q) = words.get(b'q')
        {
            self.tool = q.max(0.0) as u32;
        }
        // Plane, units.
        for g in &words.g {
            match g {
                170 => self.plane = Axis::Z,
                180 => self.plane = Axis::Y,
                190 => self.plane = Axis::X,
                200 => self.inch = true,
                210 => self.inch = false,
                _ => {}
            }
        }
        if words.g.iter().any(|g| matches!(g, 410 | 411 | 420 | 421)) {
            self.warn(
                line,
                "cutter radius compensation (G41/G42) is not applied: the programmed path is shown",
            );
        }
        // Coordinate system, distance modes, retract mode.
        for g in &words.g {
            match g {
                540..=590 if g % 10 == 0 => self
                    .params
                    .set(number::COORDINATE_SYSTEM, f64::from((g - 530) / 10)),
                591..=593 => self
                    .params
                    .set(number::COORDINATE_SYSTEM, f64::from(g - 591 + 7)),
                900 => self.absolute = true,
                910 => self.absolute = false,
                901 => self.arc_absolute = true,
                911 => self.arc_absolute = false,
                980 => self.retract_to_r = false,
                990 => self.retract_to_r = true,
                _ => {}
            }
        }
        // Non-modal codes.
        let mut axes_used = false;
        for g in &words.g {
            match g {
                100 => {
                    self.set_offsets(line, words)?;
                    axes_used = true;
                }
                280 | 300 => {
                    self.go_home(line, words, *g == 280);
                    axes_used = true;
                }
                281 | 301 => {
                    let base = if *g == 281 {
                        number::G28_HOME
                    } else {
                        number::G30_HOME
                    };
                    for i in 0..3 {
                        self.params.set(base + i, self.pos[i]);
                    }
                }
                920 => {
                    // The current point becomes the given coordinates.
                    let unit = self.unit();
                    let (work, current) = (self.work_offset(), self.g92_offset());
                    for (i, letter) in [b'x', b'y', b'z'].into_iter().enumerate() {
                        let value = match words.get(letter) {
                            Some(v) => self.pos[i] - work[i] - v * unit,
                            None => current[i],
                        };
                        self.params.set(number::G92 + i, value);
                    }
                    self.params.set(number::G92_ON, 1.0);
                    axes_used = true;
                }
                921 => {
                    for i in 0..3 {
                        self.params.set(number::G92 + i, 0.0);
                    }
                    self.params.set(number::G92_ON, 0.0);
                }
                922 => self.params.set(number::G92_ON, 0.0),
                923 => self.params.set(number::G92_ON, 1.0),
                _ => {}
            }
        }
        // Motion.
        let machine_coordinates = words.has_g(530);
        if let Some(m) = motions.last() {
            self.motion = Some(*m);
            if is_cycle(*m) {
                // A new cycle's words replace the kept ones.
                self.cycle = CycleWords::default();
            }
        }
        if self.motion.is_some_and(is_cycle) {
            for (slot, letter) in [
                (&mut self.cycle.r, b'r'),
                (&mut self.cycle.z, b'z'),
                (&mut self.cycle.q, b'q'),
                (&mut self.cycle.p, b'p'),
            ] {
                if let Some(v) = words.get(letter) {
                    *slot = Some(v);
                }
            }
        }
        let moves = !motions.is_empty() || (words.has_axes() && !axes_used);
        if moves && !axes_used && self.motion != Some(50) {
            // Only a G5 right after a G5 continues its tangent.
            self.spline_tangent = None;
        }
        if moves && !axes_used {
            match self.motion {
                None if words.has_axes() => {
                    self.warn(line, "axis words before any motion code: read as G0");
                    self.motion = Some(0);
                    self.straight(line, words, MoveKind::Rapid, machine_coordinates);
                }
                None => {}
                Some(800) if words.has_axes() => {
                    self.warn(line, "axis words with G80 (no motion): ignored");
                }
                Some(800) => {}
                Some(0) => self.straight(line, words, MoveKind::Rapid, machine_coordinates),
                Some(10 | 330 | 381..=384) => {
                    if self.motion == Some(330) {
                        self.warn(line, "G33 spindle-synchronised motion drawn as a feed");
                    }
                    self.straight(line, words, MoveKind::Feed, machine_coordinates)
                }
                Some(20 | 30) => self.arc(line, words).map_err(err)?,
                Some(50 | 51) => self.spline(line, words).map_err(err)?,
                Some(52 | 53) => {
                    self.warn(
                        line,
                        "NURBS (G5.2) are not supported: drawn as straight feeds through their control points",
                    );
                    self.straight(line, words, MoveKind::Feed, false)
                }
                Some(760) => self.warn(line, "G76 threading cycle is not supported: ignored"),
                Some(c) if is_cycle(c) => crate::cycles::run(self, line, words, c).map_err(err)?,
                Some(other) => {
                    self.warn(line, format!("G{} is not drawn", show(other)));
                }
            }
        }
        if words.m.iter().any(|m| matches!(m, 20 | 300)) {
            self.ended = true;
        }
        Ok(())
    }

    /// A straight move to the block's target (`machine`: its axis words are machine
    /// coordinates, G53).
    fn straight(&mut self, line: u32, words: &Words, kind: MoveKind, machine: bool) {
        let to = if machine {
            let mut p = self.pos;
            for (i, letter) in [b'x', b'y', b'z'].into_iter().enumerate() {
                if let Some(v) = words.get(letter) {
                    p[i] = v * self.unit();
                }
            }
            p
        } else {
            self.target(words)
        };
        self.emit(kind, line, to, None);
    }

    /// G5 (cubic, control points start + (I, J) and end + (P, Q); without I/J the last G5's
    /// tangent goes on) and G5.1 (quadratic B-spline, control point start + (I, J)) in the XY
    /// plane, drawn as feeds within 1 µm of the curve (the control polygon's second
    /// differences bound the chords' deviation).
    fn spline(&mut self, line: u32, words: &Words) -> Result<(), String> {
        if self.plane != Axis::Z {
            return Err("G5 and G5.1 splines are defined in the XY plane (G17) only".into());
        }
        let cubic = self.motion == Some(50);
        let start = self.pos;
        let end = self.target(words);
        let unit = self.unit();
        let offset = |a: u8, b: u8| -> Option<DVec3> {
            match (words.get(a), words.get(b)) {
                (None, None) => None,
                (x, y) => Some(DVec3::new(
                    x.unwrap_or(0.0) * unit,
                    y.unwrap_or(0.0) * unit,
                    0.0,
                )),
            }
        };
        let controls: Vec<DVec3> = if cubic {
            let first = match (offset(b'i', b'j'), self.spline_tangent) {
                (Some(d), _) => start + d,
                // Tangent to the last G5: its second control point mirrored through its end.
                (None, Some(c2)) => 2.0 * start - c2,
                (None, None) => return Err("the first G5 needs I and J".into()),
            };
            let Some(d2) = offset(b'p', b'q') else {
                return Err("G5 needs P and Q (the second control point from the end)".into());
            };
            vec![start, first, end + d2, end]
        } else {
            let Some(d) = offset(b'i', b'j') else {
                return Err("G5.1 needs I and J (the control point from the start)".into());
            };
            vec![start, start + d, end]
        };
        // Chords within 1 µm: a Bézier of degree n deviates from its n-chord polyline by at
        // most n(n − 1) max|ΔΔP| / (8 k²) with k chords.
        let degree = (controls.len() - 1) as f64;
        let second = controls
            .windows(3)
            .map(|w| (w[0] - 2.0 * w[1] + w[2]).length())
            .fold(0.0, f64::max);
        let chords = ((degree * (degree - 1.0) * second / (8.0 * 1e-3))
            .sqrt()
            .ceil() as usize)
            .clamp(1, 4096);
        for k in 1..=chords {
            let t = k as f64 / chords as f64;
            let p = if k == chords {
                end
            } else {
                de_casteljau(&controls, t)
            };
            // The axial coordinate moves linearly (a spline is planar in XY).
            let mut p = p;
            p.z = start.z + (end.z - start.z) * t;
            self.emit(MoveKind::Feed, line, p, None);
        }
        self.spline_tangent = cubic.then_some(controls[2]);
        Ok(())
    }

    /// G2/G3: an arc or helix in the plane, about a centre from I/J/K or R.
    fn arc(&mut self, line: u32, words: &Words) -> Result<(), String> {
        let clockwise = self.motion == Some(20);
        let (u, v, _) = self.plane_axes();
        let start = self.pos;
        let end = self.target(words);
        let unit = self.unit();
        let letters = [b'i', b'j', b'k'];
        let mut centre = start;
        if let Some(r) = words.get(b'r') {
            let r = r * unit;
            let (a, b) = (
                glam::DVec2::new(start[u], start[v]),
                glam::DVec2::new(end[u], end[v]),
            );
            let chord = b - a;
            let d = chord.length();
            if d < 1e-9 {
                return Err("an R-form arc's end is its start: a full circle needs I/J/K".into());
            }
            let half = 0.5 * d;
            let h2 = r * r - half * half;
            if h2 < -(1e-3 * r.abs()).max(1e-4) * r.abs() {
                self.warn(
                    line,
                    format!(
                        "arc radius {:.4} mm is shorter than half the chord ({half:.4} mm): drawn as a half circle",
                        r.abs()
                    ),
                );
            }
            let h = h2.max(0.0).sqrt();
            // The short arc's centre lies left of the chord for G3, right for G2; a negative R
            // asks for the long arc.
            let left = glam::DVec2::new(-chord.y, chord.x) / d;
            let side = if clockwise { -1.0 } else { 1.0 } * r.signum();
            let c = 0.5 * (a + b) + side * h * left;
            centre[u] = c.x;
            centre[v] = c.y;
        } else {
            let (lu, lv) = (letters[u], letters[v]);
            if words.get(lu).is_none() && words.get(lv).is_none() {
                return Err(format!(
                    "an arc without its centre: {}/{} or R expected",
                    (lu as char).to_ascii_uppercase(),
                    (lv as char).to_ascii_uppercase()
                ));
            }
            let offset = self.offset();
            for (axis, letter) in [(u, lu), (v, lv)] {
                let value = words.get(letter).unwrap_or(0.0) * unit;
                centre[axis] = if self.arc_absolute {
                    value + offset[axis]
                } else {
                    start[axis] + value
                };
            }
            let r0 = glam::DVec2::new(start[u] - centre[u], start[v] - centre[v]).length();
            let r1 = glam::DVec2::new(end[u] - centre[u], end[v] - centre[v]).length();
            if (r0 - r1).abs() > (1e-3 * r0.max(r1)).max(0.002) {
                self.warn(
                    line,
                    format!(
                        "arc radius differs from start ({r0:.4} mm) to end ({r1:.4} mm): drawn as a spiral between them"
                    ),
                );
            }
        }
        let a0 = (start[v] - centre[v]).atan2(start[u] - centre[u]);
        let a1 = (end[v] - centre[v]).atan2(end[u] - centre[u]);
        let tau = std::f64::consts::TAU;
        let mut angle = a1 - a0;
        if clockwise {
            while angle >= -1e-12 {
                angle -= tau;
            }
            while angle < -tau - 1e-12 {
                angle += tau;
            }
        } else {
            while angle <= 1e-12 {
                angle += tau;
            }
            while angle > tau + 1e-12 {
                angle -= tau;
            }
        }
        let extra = match words.get(b'p') {
            Some(p) if p >= 1.0 && p.fract() == 0.0 && p <= MAX_TURNS => p - 1.0,
            Some(p) => {
                self.warn(
                    line,
                    format!("arc turns P{p} is not a whole number from 1 to {MAX_TURNS}: P1 used"),
                );
                0.0
            }
            None => 0.0,
        };
        angle += extra * tau * angle.signum();
        self.emit(MoveKind::Arc, line, end, Some((centre, angle / tau)));
        Ok(())
    }

    /// G28/G30: through the block's axis words (if any) to the stored home, rapid.
    fn go_home(&mut self, line: u32, words: &Words, g28: bool) {
        let base = if g28 {
            number::G28_HOME
        } else {
            number::G30_HOME
        };
        let home = DVec3::new(
            self.params.get(base),
            self.params.get(base + 1),
            self.params.get(base + 2),
        );
        if words.has_axes() {
            let via = self.target(words);
            self.emit(MoveKind::Rapid, line, via, None);
            let mut to = self.pos;
            for (i, letter) in [b'x', b'y', b'z'].into_iter().enumerate() {
                if words.get(letter).is_some() {
                    to[i] = home[i];
                }
            }
            self.emit(MoveKind::Rapid, line, to, None);
        } else {
            self.emit(MoveKind::Rapid, line, home, None);
        }
    }

    /// G10 L2 (a coordinate system's offsets) and L20 (offsets that make the current point
    /// the given coordinates); other G10 forms (tool tables) are ignored.
    fn set_offsets(&mut self, line: u32, words: &Words) -> Result<(), GcodeError> {
        let l = words.get(b'l').unwrap_or(0.0);
        if l != 2.0 && l != 20.0 {
            return Ok(());
        }
        let p = words.get(b'p').unwrap_or(0.0);
        if !(0.0..=9.0).contains(&p) || p.fract() != 0.0 {
            return Err(GcodeError::Run {
                line,
                message: format!("G10 L{l} P{p}: P must be 0–9"),
            });
        }
        let system = if p == 0.0 {
            self.params.get(number::COORDINATE_SYSTEM).round() as usize
        } else {
            p as usize
        }
        .clamp(1, 9);
        let base = number::G54 + 20 * (system - 1);
        let g92 = self.g92_offset();
        for (i, letter) in [b'x', b'y', b'z'].into_iter().enumerate() {
            if let Some(v) = words.get(letter) {
                let value = if l == 2.0 {
                    v * self.unit()
                } else {
                    self.pos[i] - g92[i] - v * self.unit()
                };
                self.params.set(base + i, value);
            }
        }
        Ok(())
    }
}

/// The point at `t` of the Bézier curve of `controls`.
fn de_casteljau(controls: &[DVec3], t: f64) -> DVec3 {
    let mut points = controls.to_vec();
    for level in 1..points.len() {
        for i in 0..points.len() - level {
            points[i] = points[i].lerp(points[i + 1], t);
        }
    }
    points[0]
}

/// Whether `g` is a motion code (modal group 1).
fn is_motion(g: Code) -> bool {
    matches!(
        g,
        0 | 10 | 20 | 30 | 50 | 51 | 52 | 53 | 330 | 381..=384 | 760 | 800
    ) || is_cycle(g)
}

/// Whether `g` is a canned cycle.
pub(crate) fn is_cycle(g: Code) -> bool {
    matches!(g, 730 | 740) || ((810..=890).contains(&g) && g.is_multiple_of(10))
}

/// Whether `g` is read (run or deliberately without effect on the path).
fn is_known_g(g: Code) -> bool {
    is_motion(g)
        || matches!(
            g,
            40 | 100
                | 170
                | 171
                | 180
                | 181
                | 190
                | 191
                | 200
                | 210
                | 280
                | 281
                | 300
                | 301
                | 400
                | 410
                | 411
                | 420
                | 421
                | 430
                | 431
                | 432
                | 490
                | 530
                | 540
                | 550
                | 560
                | 570
                | 580
                | 590
                | 591
                | 592
                | 593
                | 610
                | 611
                | 640
                | 900
                | 901
                | 910
                | 911
                | 920
                | 921
                | 922
                | 923
                | 930
                | 940
                | 950
                | 960
                | 970
                | 980
                | 990
        )
}

/// A code ×10 as written (`593` → `59.3`).
pub(crate) fn show(code: Code) -> String {
    if code.is_multiple_of(10) {
        format!("{}", code / 10)
    } else {
        format!("{}.{}", code / 10, code % 10)
    }
}

fn codes(list: &[Code], letter: char) -> String {
    list.iter()
        .map(|c| format!("{letter}{}", show(*c)))
        .collect::<Vec<_>>()
        .join(", ")
}
