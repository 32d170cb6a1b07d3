//! The program's parameters: numbered `#1`–`#5602` (`#1`–`#30` local to each subroutine
//! call, where its arguments land; the rest global, among them the machine's offsets and
//! homes at LinuxCNC's numbers), named locals `#<name>` (per call) and named globals
//! `#<_name>`.

use std::collections::HashMap;

/// The highest parameter number.
pub const MAX_PARAMETER: usize = 5602;
/// Parameters local to a subroutine call: `#1`–`#30`.
const LOCALS: usize = 30;

/// LinuxCNC's parameter numbers that the interpreter reads and writes.
pub(crate) mod number {
    /// G28 home, machine coordinates (X, Y, Z; then A, B, C).
    pub const G28_HOME: usize = 5161;
    /// G30 home.
    pub const G30_HOME: usize = 5181;
    /// 1 when the G92 offsets apply.
    pub const G92_ON: usize = 5210;
    /// G92 offsets (X, Y, Z, …).
    pub const G92: usize = 5211;
    /// The active coordinate system, 1 (G54) to 9 (G59.3).
    pub const COORDINATE_SYSTEM: usize = 5220;
    /// G54's offsets; each next system's 20 further on.
    pub const G54: usize = 5221;
    /// The tool in the spindle.
    pub const TOOL: usize = 5400;
}

/// One subroutine call's local parameters.
#[derive(Clone, Debug, Default)]
struct Frame {
    numbered: [f64; LOCALS],
    named: HashMap<String, f64>,
}

/// Every parameter.
#[derive(Clone, Debug)]
pub struct Params {
    /// `#31`–`#5602` at index `n`; lower indices unused.
    global: Vec<f64>,
    /// The call stack's frames, the main program's first.
    frames: Vec<Frame>,
    named_global: HashMap<String, f64>,
}

impl Default for Params {
    fn default() -> Self {
        let mut global = vec![0.0; MAX_PARAMETER + 1];
        global[number::COORDINATE_SYSTEM] = 1.0;
        Params {
            global,
            frames: vec![Frame::default()],
            named_global: HashMap::new(),
        }
    }
}

impl Params {
    /// The index of a parameter number, `None` outside 1–5602 or not whole.
    fn index(n: f64) -> Option<usize> {
        let rounded = n.round();
        ((rounded - n).abs() < 1e-4 && (1.0..=MAX_PARAMETER as f64).contains(&rounded))
            .then_some(rounded as usize)
    }

    /// Numbered parameter `n`'s value, `None` for a number outside 1–5602.
    pub fn numbered(&self, n: f64) -> Option<f64> {
        let i = Params::index(n)?;
        Some(self.get(i))
    }

    /// Parameter `i` (1–5602).
    pub(crate) fn get(&self, i: usize) -> f64 {
        if (1..=LOCALS).contains(&i) {
            self.frames.last().map_or(0.0, |f| f.numbered[i - 1])
        } else {
            self.global.get(i).copied().unwrap_or(0.0)
        }
    }

    /// Sets numbered parameter `n`; `false` for a number outside 1–5602.
    pub fn set_numbered(&mut self, n: f64, value: f64) -> bool {
        match Params::index(n) {
            Some(i) => {
                self.set(i, value);
                true
            }
            None => false,
        }
    }

    pub(crate) fn set(&mut self, i: usize, value: f64) {
        if (1..=LOCALS).contains(&i) {
            if let Some(f) = self.frames.last_mut() {
                f.numbered[i - 1] = value;
            }
        } else if let Some(slot) = self.global.get_mut(i) {
            *slot = value;
        }
    }

    /// A named parameter (a global when it starts with `_`), `None` when unset.
    pub fn named(&self, name: &str) -> Option<f64> {
        if name.starts_with('_') {
            self.named_global.get(name).copied()
        } else {
            self.frames.last().and_then(|f| f.named.get(name).copied())
        }
    }

    /// Sets a named parameter.
    pub fn set_named(&mut self, name: &str, value: f64) {
        if name.starts_with('_') {
            self.named_global.insert(name.to_string(), value);
        } else if let Some(f) = self.frames.last_mut() {
            f.named.insert(name.to_string(), value);
        }
    }

    /// Enters a subroutine with `args` in `#1`…
    pub(crate) fn push_call(&mut self, args: &[f64]) {
        let mut frame = Frame::default();
        for (slot, a) in frame.numbered.iter_mut().zip(args) {
            *slot = *a;
        }
        self.frames.push(frame);
    }

    /// Leaves a subroutine (the main program's frame stays).
    pub(crate) fn pop_call(&mut self) {
        if self.frames.len() > 1 {
            self.frames.pop();
        }
    }
}
