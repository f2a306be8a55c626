//! A child's output condensed: each distinct line kept once, in order of first appearance, with
//! the number of times it was printed (gmsh prints one line per failing entity, thousands of
//! identical lines; [`super::process`] reads its output through this).

use std::collections::HashMap;

/// Distinct lines kept by [`Condensed`]; later distinct lines are only counted.
const MAX_DISTINCT: usize = 200;
/// Longest line kept (bytes); longer lines are cut.
const MAX_LINE: usize = 500;

/// A child's output (stdout then stderr lines, in order of first appearance), each distinct
/// line once with the number of times it was printed.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Condensed {
    /// `(line, count)`, in order of first appearance (at most 200 distinct lines).
    pub lines: Vec<(String, usize)>,
    /// Lines not kept because 200 distinct lines were already kept.
    pub dropped: usize,
}

impl Condensed {
    /// Counts the lines of `text`.
    pub fn from_text(text: &str) -> Self {
        let mut c = Counter::default();
        for l in text.lines() {
            c.add(l);
        }
        c.done()
    }

    /// The lines `keep` accepts, each as `line` or `line (×n)` when printed n > 1 times, joined
    /// by newlines.
    pub fn render(&self, keep: impl Fn(&str) -> bool) -> String {
        let mut out: Vec<String> = self
            .lines
            .iter()
            .filter(|(l, _)| keep(l))
            .map(|(l, n)| {
                if *n > 1 {
                    format!("{l} (×{n})")
                } else {
                    l.clone()
                }
            })
            .collect();
        if self.dropped > 0 {
            out.push(format!("… and {} more lines", self.dropped));
        }
        out.join("\n")
    }

    /// Total number of lines printed.
    pub fn total(&self) -> usize {
        self.lines.iter().map(|(_, n)| n).sum::<usize>() + self.dropped
    }
}

#[derive(Default)]
pub(super) struct Counter {
    index: HashMap<String, usize>,
    out: Condensed,
}

impl Counter {
    pub(super) fn add(&mut self, line: &str) {
        self.add_n(line, 1);
    }

    pub(super) fn add_n(&mut self, line: &str, n: usize) {
        let mut line = line.trim_end();
        if line.len() > MAX_LINE {
            let mut cut = MAX_LINE;
            while !line.is_char_boundary(cut) {
                cut -= 1;
            }
            line = &line[..cut];
        }
        if let Some(&i) = self.index.get(line) {
            self.out.lines[i].1 += n;
        } else if self.out.lines.len() < MAX_DISTINCT {
            self.index.insert(line.to_string(), self.out.lines.len());
            self.out.lines.push((line.to_string(), n));
        } else {
            self.out.dropped += n;
        }
    }

    /// Counts `n` lines dropped elsewhere (by another counter).
    pub(super) fn add_dropped(&mut self, n: usize) {
        self.out.dropped += n;
    }

    pub(super) fn done(self) -> Condensed {
        self.out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeated_lines_are_counted_once_in_order() {
        let c = Condensed::from_text("a\nb\na\na\nc\n");
        assert_eq!(
            c.lines,
            vec![("a".into(), 3), ("b".into(), 1), ("c".into(), 1)]
        );
        assert_eq!(c.total(), 5);
        assert_eq!(c.render(|l| l != "b"), "a (×3)\nc");
    }

    #[test]
    fn distinct_lines_are_bounded() {
        let text: String = (0..MAX_DISTINCT + 7)
            .map(|i| format!("line {i}\n"))
            .collect();
        let c = Condensed::from_text(&text);
        assert_eq!(c.lines.len(), MAX_DISTINCT);
        assert_eq!(c.dropped, 7);
        assert!(c.render(|_| true).ends_with("… and 7 more lines"));
    }
}
