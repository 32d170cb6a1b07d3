//! The program run line by line: every line read first (in parallel; lines are independent),
//! the o-word labels indexed, then the lines executed in order with o-word control flow
//! (subroutines, conditionals, loops) on a program counter, bounded by [`Limits`].

use std::collections::HashMap;

use rayon::prelude::*;

use crate::expr::{Expr, eval};
use crate::lex::{Keyword, Statement, Target, Word, statement};
use crate::machine::{Machine, Words};
use crate::{GcodeError, Limits, Program};

/// Where each o-word label is used: line indices and keywords, in order.
type Labels<'a> = HashMap<&'a str, Vec<(usize, Keyword)>>;

/// A subroutine call on the stack.
struct Call {
    /// The line index to go on from.
    back: usize,
}

/// Runs the program `text`.
pub(crate) fn run(text: &str, limits: &Limits) -> Program {
    let lines: Vec<&str> = text.lines().collect();
    let statements: Vec<Statement> = lines
        .par_iter()
        .enumerate()
        .map(|(i, l)| statement(l, i as u32 + 1))
        .collect();
    let mut labels: Labels<'_> = HashMap::new();
    for (i, s) in statements.iter().enumerate() {
        if let Statement::OWord { label, keyword, .. } = s {
            labels
                .entry(label.as_str())
                .or_default()
                .push((i, *keyword));
        }
    }
    let mut run = Run {
        statements: &statements,
        labels: &labels,
        machine: Machine::new(limits),
        calls: Vec::new(),
        repeats: HashMap::new(),
    };
    run.execute(limits);
    let Run { mut machine, .. } = run;
    if machine.more_warnings > 0 {
        let more = machine.more_warnings;
        machine.warnings.push(crate::Warning {
            line: 0,
            message: format!("{more} more warnings not listed"),
        });
    }
    Program {
        units: "mm",
        program_units: if machine.inch { "inch" } else { "mm" },
        moves: machine.moves,
        warnings: machine.warnings,
    }
}

struct Run<'a> {
    statements: &'a [Statement],
    labels: &'a Labels<'a>,
    machine: Machine,
    calls: Vec<Call>,
    /// Repeats left, by (call depth, the `repeat` line).
    repeats: HashMap<(usize, usize), u64>,
}

impl Run<'_> {
    fn execute(&mut self, limits: &Limits) {
        let mut pc = 0usize;
        let mut blocks = 0u64;
        let mut percents = 0;
        while pc < self.statements.len() {
            blocks += 1;
            let line = pc as u32 + 1;
            if blocks > limits.max_blocks {
                self.machine.warn(
                    line,
                    format!(
                        "stopped after {} blocks (a loop that does not end?)",
                        limits.max_blocks
                    ),
                );
                return;
            }
            if self.machine.moves.len() >= limits.max_moves {
                self.machine
                    .warn(line, format!("stopped at {} moves", limits.max_moves));
                return;
            }
            let next = match &self.statements[pc] {
                Statement::Empty => pc + 1,
                Statement::Percent => {
                    percents += 1;
                    if percents == 2 {
                        return;
                    }
                    pc + 1
                }
                Statement::Bad(e) => {
                    self.machine
                        .warn(line, format!("{}: line skipped", e.message()));
                    pc + 1
                }
                Statement::Block { words, settings } => {
                    if let Err(e) = self.block(line, words, settings) {
                        self.machine
                            .warn(line, format!("{}: line skipped", e.message()));
                    }
                    if self.machine.ended {
                        return;
                    }
                    pc + 1
                }
                Statement::OWord {
                    label,
                    keyword,
                    args,
                } => match self.oword(pc, label, *keyword, args) {
                    Ok(Some(next)) => next,
                    Ok(None) => return,
                    Err(e) => {
                        self.machine.warn(line, e.message());
                        pc + 1
                    }
                },
            };
            pc = next;
        }
    }

    /// Evaluates a block's words and settings (values read before any is set), sets the
    /// parameters, then runs the words.
    fn block(
        &mut self,
        line: u32,
        words: &[Word],
        settings: &[(Target, Expr)],
    ) -> Result<(), GcodeError> {
        let params = &self.machine.params;
        let mut evaluated = Words::default();
        for w in words {
            let v = eval(&w.value, params, line)?;
            match w.letter {
                b'g' | b'm' => {
                    let code = (v * 10.0).round();
                    if (v * 10.0 - code).abs() > 1e-6 || !(0.0..=1e5).contains(&code) {
                        return Err(GcodeError::Run {
                            line,
                            message: format!(
                                "{}{v} is not a code",
                                (w.letter as char).to_ascii_uppercase()
                            ),
                        });
                    }
                    if w.letter == b'g' {
                        evaluated.g.push(code as u32);
                    } else {
                        evaluated.m.push(code as u32);
                    }
                }
                b'n' => {}
                letter => {
                    let slot = &mut evaluated.values[(letter - b'a') as usize];
                    if slot.is_some() {
                        return Err(GcodeError::Run {
                            line,
                            message: format!(
                                "two {} words on one line",
                                (letter as char).to_ascii_uppercase()
                            ),
                        });
                    }
                    *slot = Some(v);
                }
            }
        }
        let mut sets = Vec::with_capacity(settings.len());
        for (target, value) in settings {
            let value = eval(value, params, line)?;
            let target = match target {
                Target::Numbered(n) => Ok(eval(n, params, line)?),
                Target::Named(name) => Err(name.as_str()),
            };
            sets.push((target, value));
        }
        for (target, value) in sets {
            match target {
                Ok(n) => {
                    if !self.machine.params.set_numbered(n, value) {
                        return Err(GcodeError::Run {
                            line,
                            message: format!("#{n} is not a parameter number (1–5602)"),
                        });
                    }
                }
                Err(name) => self.machine.params.set_named(name, value),
            }
        }
        if words.is_empty() {
            return Ok(());
        }
        self.machine.run_block(line, &evaluated)
    }

    /// The next line index with `label` after `pc` whose keyword is one of `kinds`.
    fn next_of(&self, label: &str, pc: usize, kinds: &[Keyword]) -> Option<(usize, Keyword)> {
        self.labels
            .get(label)?
            .iter()
            .find(|(i, k)| *i > pc && kinds.contains(k))
            .copied()
    }

    /// The last line index with `label` before `pc` whose keyword is `kind`.
    fn previous_of(&self, label: &str, pc: usize, kind: Keyword) -> Option<usize> {
        self.labels
            .get(label)?
            .iter()
            .rev()
            .find(|(i, k)| *i < pc && *k == kind)
            .map(|(i, _)| *i)
    }

    /// Whether `label`'s loop is a `do … while` (its `while` is the loop's end).
    fn is_do_loop(&self, label: &str, pc: usize) -> bool {
        self.previous_of(label, pc, Keyword::Do).is_some()
            && self
                .next_of(label, pc, &[Keyword::EndWhile])
                .is_none_or(|(i, _)| self.previous_of(label, i, Keyword::While) != Some(pc))
    }

    fn condition(&self, pc: usize, args: &[Expr]) -> Result<bool, GcodeError> {
        let line = pc as u32 + 1;
        let Some(e) = args.first() else {
            return Err(GcodeError::Run {
                line,
                message: "a condition [ … ] expected".into(),
            });
        };
        Ok(eval(e, &self.machine.params, line)? != 0.0)
    }

    /// Runs the o-word at `pc`: the next line index, `None` to stop.
    fn oword(
        &mut self,
        pc: usize,
        label: &str,
        keyword: Keyword,
        args: &[Expr],
    ) -> Result<Option<usize>, GcodeError> {
        let line = pc as u32 + 1;
        let missing = |what: &str| GcodeError::Run {
            line,
            message: format!("o{label} {what}"),
        };
        let after = |found: Option<(usize, Keyword)>, what: &str| {
            found.map(|(i, _)| Some(i + 1)).ok_or_else(|| missing(what))
        };
        match keyword {
            // A definition met in the program's flow is skipped.
            Keyword::Sub => after(
                self.next_of(label, pc, &[Keyword::EndSub]),
                "sub has no endsub",
            ),
            Keyword::EndSub | Keyword::Return => {
                if keyword == Keyword::Return
                    && let Some(e) = args.first()
                {
                    let v = eval(e, &self.machine.params, line)?;
                    self.machine.params.set_named("_value", v);
                }
                match self.calls.pop() {
                    Some(call) => {
                        self.repeats
                            .retain(|(depth, _), _| *depth <= self.calls.len());
                        self.machine.params.pop_call();
                        Ok(Some(call.back))
                    }
                    // An endsub reached outside a call (a definition's end): go on.
                    None => Ok(Some(pc + 1)),
                }
            }
            Keyword::Call => {
                let Some(start) = self
                    .labels
                    .get(label)
                    .and_then(|uses| uses.iter().find(|(_, k)| *k == Keyword::Sub))
                    .map(|(i, _)| *i)
                else {
                    return Err(missing("call: no such subroutine"));
                };
                if self.calls.len() >= self.machine.limits.max_call_depth {
                    return Err(missing("call: calls nested too deeply"));
                }
                let values = args
                    .iter()
                    .map(|a| eval(a, &self.machine.params, line))
                    .collect::<Result<Vec<f64>, _>>()?;
                self.calls.push(Call { back: pc + 1 });
                self.machine.params.push_call(&values);
                Ok(Some(start + 1))
            }
            Keyword::If => {
                if self.condition(pc, args)? {
                    return Ok(Some(pc + 1));
                }
                let mut at = pc;
                loop {
                    let Some((i, k)) =
                        self.next_of(label, at, &[Keyword::ElseIf, Keyword::Else, Keyword::EndIf])
                    else {
                        return Err(missing("if has no endif"));
                    };
                    if k != Keyword::ElseIf {
                        return Ok(Some(i + 1));
                    }
                    let Statement::OWord { args, .. } = &self.statements[i] else {
                        return Ok(Some(i + 1));
                    };
                    if self.condition(i, args)? {
                        return Ok(Some(i + 1));
                    }
                    at = i;
                }
            }
            // Reached after a branch ran: past the endif.
            Keyword::ElseIf | Keyword::Else => {
                after(self.next_of(label, pc, &[Keyword::EndIf]), "has no endif")
            }
            Keyword::EndIf | Keyword::Do => Ok(Some(pc + 1)),
            Keyword::While if self.is_do_loop(label, pc) => {
                if self.condition(pc, args)? {
                    let start = self.previous_of(label, pc, Keyword::Do).unwrap_or(pc);
                    Ok(Some(start + 1))
                } else {
                    Ok(Some(pc + 1))
                }
            }
            Keyword::While => {
                if self.condition(pc, args)? {
                    Ok(Some(pc + 1))
                } else {
                    after(
                        self.next_of(label, pc, &[Keyword::EndWhile]),
                        "while has no endwhile",
                    )
                }
            }
            Keyword::EndWhile => self
                .previous_of(label, pc, Keyword::While)
                .map(Some)
                .ok_or_else(|| missing("endwhile has no while")),
            Keyword::Repeat => {
                let key = (self.calls.len(), pc);
                if !self.repeats.contains_key(&key) {
                    let n = match args.first() {
                        Some(e) => eval(e, &self.machine.params, line)?,
                        None => return Err(missing("repeat needs a count [ … ]")),
                    };
                    self.repeats.insert(key, n.max(0.0).round() as u64);
                }
                if self.repeats.get(&key).copied().unwrap_or(0) == 0 {
                    self.repeats.remove(&key);
                    return after(
                        self.next_of(label, pc, &[Keyword::EndRepeat]),
                        "repeat has no endrepeat",
                    );
                }
                Ok(Some(pc + 1))
            }
            Keyword::EndRepeat => {
                let start = self
                    .previous_of(label, pc, Keyword::Repeat)
                    .ok_or_else(|| missing("endrepeat has no repeat"))?;
                if let Some(left) = self.repeats.get_mut(&(self.calls.len(), start)) {
                    *left = left.saturating_sub(1);
                }
                Ok(Some(start))
            }
            Keyword::Break | Keyword::Continue => {
                let end = self
                    .labels
                    .get(label)
                    .and_then(|uses| {
                        uses.iter().find(|(i, k)| {
                            *i > pc
                                && (matches!(k, Keyword::EndWhile | Keyword::EndRepeat)
                                    || (*k == Keyword::While && self.is_do_loop(label, *i)))
                        })
                    })
                    .copied();
                let Some((i, k)) = end else {
                    return Err(missing("break/continue outside its loop"));
                };
                if keyword == Keyword::Continue {
                    return Ok(Some(i));
                }
                if k == Keyword::EndRepeat
                    && let Some(start) = self.previous_of(label, i, Keyword::Repeat)
                {
                    self.repeats.remove(&(self.calls.len(), start));
                }
                Ok(Some(i + 1))
            }
        }
    }
}
