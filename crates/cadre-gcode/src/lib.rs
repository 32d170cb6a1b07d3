//! An interpreter of CAM programs in ISO 6983 / RS-274 G-code, as machine controllers and
//! CAM post-processors write it, including the RS-274/NGC dialect LinuxCNC documents: the
//! program is read into the moves the tool makes ([`Program::moves`]), for cadre to draw as
//! a toolpath and for other tools to check.
//!
//! Read: G0 rapids, G1 feeds, G2/G3 arcs and helices in the G17/G18/G19 planes with I/J/K
//! centres (incremental, or absolute after G90.1) or an R radius, with P turns; G20/G21 units
//! (every output is in mm); G90/G91; G53 machine moves; the G54–G59.3 work offsets (and G10 L2
//! / L20 setting them); G92 offsets (G92.1–G92.3); G28/G30 homes (G28.1/G30.1 set); canned
//! cycles G81–G89 with G98/G99, R, Q, P and L repeats, and G80; feeds, tool changes (T, M6),
//! comments and block numbers; numbered and named parameters (`#1`, `#<depth>`, globals
//! `#<_name>`) with bracketed expressions and the language's functions; o-word subroutines
//! (`sub`/`endsub`/`return`/`call` with arguments in `#1`–`#30`), `if`/`elseif`/`else`,
//! `while`, `do`…`while`, `repeat`, `break`, `continue`, all bounded ([`Limits`]).
//!
//! G5 cubic splines (a next G5 without I/J continuing the last's tangent) and G5.1 quadratic
//! B-splines in the XY plane, drawn as feeds within 1 µm of the curve.
//!
//! Not supported, warned with their line while the rest still loads: cutter radius
//! compensation (G41/G42: the programmed path is shown), NURBS (G5.2: drawn through their
//! control points), threading (G33, G76), inverse-time semantics (the F value is kept as read), rotary
//! axes (A, B, C), Fanuc M98/M99 subprograms. Nothing panics; a line that does not parse is
//! a warning naming it, and the program goes on.
//!
//! ```
//! let program = cadre_gcode::interpret("G21 G90\nG0 X10 Y0 Z5\nG1 Z-1 F200\nG3 X-10 Y0 I-10 J0\n");
//! assert_eq!(program.moves.len(), 3);
//! assert!((program.moves[2].turns.unwrap() - 0.5).abs() < 1e-12);
//! assert!(program.warnings.is_empty());
//! ```

mod cycles;
mod expr;
mod flow;
mod lex;
mod machine;
mod params;
mod sample;

pub use params::Params;
pub use sample::{MAX_PATH_POINTS, PathRun, sample_moves};

use serde::Serialize;

/// What a line could not be read or run as.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GcodeError {
    /// The line does not parse.
    #[error("line {line}, column {column}: {message}")]
    Syntax {
        /// 1-based line.
        line: u32,
        /// 1-based column in the line without its spaces and comments.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// An expression has no value (division by zero, an unset parameter, …).
    #[error("line {line}: {message}")]
    Eval {
        /// 1-based line.
        line: u32,
        /// What is wrong.
        message: String,
    },
    /// The line parses but cannot be run (an arc without a centre, two motions, …).
    #[error("line {line}: {message}")]
    Run {
        /// 1-based line.
        line: u32,
        /// What is wrong.
        message: String,
    },
}

impl GcodeError {
    /// What is wrong, without the line (which a [`Warning`] carries), with the column where
    /// there is one.
    pub fn message(&self) -> String {
        match self {
            GcodeError::Syntax {
                column, message, ..
            } => format!("column {column}: {message}"),
            GcodeError::Eval { message, .. } | GcodeError::Run { message, .. } => message.clone(),
        }
    }
}

/// What kind of move.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum MoveKind {
    /// G0 (and the rapids of canned cycles, homes).
    Rapid,
    /// G1 (and the feeds of canned cycles).
    Feed,
    /// G2/G3: an arc or a helix.
    Arc,
}

/// The plane axis an arc turns about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    /// G19: the YZ plane.
    X,
    /// G18: the ZX plane.
    Y,
    /// G17: the XY plane.
    Z,
}

/// One move of the tool, from where the previous one ended (the first from the machine's
/// origin, where the program starts).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Move {
    /// Rapid, feed or arc.
    pub kind: MoveKind,
    /// The 1-based line that made it.
    pub line: u32,
    /// Where it ends, in the program's coordinate system (the work offset and G92 offset in
    /// force at the move not added), mm.
    pub end: [f64; 3],
    /// An arc's centre, program coordinates, mm, at the start's height along its axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub centre: Option<[f64; 3]>,
    /// An arc's signed turns: its angle over 2π, positive counter-clockwise (G3) seen from
    /// the positive side of its axis, negative clockwise (G2).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub turns: Option<f64>,
    /// An arc's axis (its plane's normal).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub axis: Option<Axis>,
    /// The feed rate in force, mm/min (as read under G93/G95), 0 for rapids.
    pub feed: f64,
    /// The tool in the spindle (0: none).
    pub tool: u32,
    /// What the program's coordinates are offset by on the machine (work offset + G92), mm:
    /// machine position = `end` + `offset`.
    pub offset: [f64; 3],
}

impl Move {
    /// Where it ends on the machine, mm.
    pub fn machine_end(&self) -> glam::DVec3 {
        glam::DVec3::from(self.end) + glam::DVec3::from(self.offset)
    }
}

/// Something in the program that was not run as written.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Warning {
    /// The 1-based line.
    pub line: u32,
    /// What and why.
    pub message: String,
}

/// An interpreted program.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Program {
    /// The units every figure is in: always `"mm"` (inch programs are converted).
    pub units: &'static str,
    /// The units the program was written in at its end (`"mm"` or `"inch"`).
    pub program_units: &'static str,
    /// The moves, in program order.
    pub moves: Vec<Move>,
    /// What was not run as written, in order; at most [`Limits::max_warnings`], then one
    /// saying how many more there were.
    pub warnings: Vec<Warning>,
}

/// Bounds on what a program may make the interpreter do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Blocks executed in all (loops and calls counted each time): past this the program
    /// stops with a warning.
    pub max_blocks: u64,
    /// Moves in all.
    pub max_moves: usize,
    /// Nested subroutine calls.
    pub max_call_depth: usize,
    /// Warnings kept.
    pub max_warnings: usize,
}

impl Default for Limits {
    /// 100 million blocks, 50 million moves, 64 nested calls, 1,000 warnings.
    fn default() -> Self {
        Limits {
            max_blocks: 100_000_000,
            max_moves: 50_000_000,
            max_call_depth: 64,
            max_warnings: 1000,
        }
    }
}

/// The file extensions CAM post-processors give programs (compared without case).
pub const PROGRAM_EXTENSIONS: [&str; 9] = [
    "ngc", "nc", "gcode", "gc", "tap", "cnc", "iso", "mpf", "eia",
];

/// Whether `path` names a CAM program, by its extension ([`PROGRAM_EXTENSIONS`]).
pub fn is_program_path(path: &std::path::Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| PROGRAM_EXTENSIONS.iter().any(|x| e.eq_ignore_ascii_case(x)))
}

/// Interprets `text` with the default [`Limits`].
pub fn interpret(text: &str) -> Program {
    interpret_with(text, &Limits::default())
}

/// Interprets `text` within `limits`.
pub fn interpret_with(text: &str, limits: &Limits) -> Program {
    flow::run(text, limits)
}
