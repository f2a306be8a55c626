//! Frame sinks of a run: several sinks as one ([`Fanout`]), and a set of sinks handed to a run
//! as one optional sink.

use crate::error::Result;
use crate::math::gcd;
use crate::time::{Frame, FrameSink, Sink};

/// Calls `f` with `sinks` as one optional sink (none, the one, or a [`Fanout`] of several).
pub(super) fn with_sinks<R>(
    sinks: &mut [&mut dyn FrameSink],
    f: impl FnOnce(Sink<'_>) -> Result<R>,
) -> Result<R> {
    match sinks {
        [] => f(None),
        [one] => f(Some(&mut **one)),
        many => {
            let mut fan = Fanout::new(many);
            f(Some(&mut fan))
        }
    }
}

/// Several sinks as one: frames every gcd of their intervals, each sink handed the frames at
/// its own interval.
pub struct Fanout<'s, 'a> {
    sinks: &'s mut [&'a mut dyn FrameSink],
    every: usize,
}

impl<'s, 'a> Fanout<'s, 'a> {
    /// Fans frames out to `sinks` (their intervals are read once, here).
    pub fn new(sinks: &'s mut [&'a mut dyn FrameSink]) -> Self {
        let every = sinks.iter().fold(0, |g, s| gcd(g, s.every()));
        Self { sinks, every }
    }
}

impl FrameSink for Fanout<'_, '_> {
    fn every(&self) -> usize {
        self.every
    }

    fn wants(&self, step: usize) -> bool {
        self.sinks
            .iter()
            .any(|s| s.every() > 0 && step.is_multiple_of(s.every()) && s.wants(step))
    }

    fn frame(&mut self, frame: &Frame<'_>) -> Result<()> {
        for s in self.sinks.iter_mut() {
            let e = s.every();
            if e > 0 && frame.step.is_multiple_of(e) {
                s.frame(frame)?;
            }
        }
        Ok(())
    }
}
