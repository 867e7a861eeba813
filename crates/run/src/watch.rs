//! What a command file's run tells whoever watches it as it goes: `linkage run` draws the
//! progress bar of `linkage simulate` from it on a terminal.

use std::sync::Arc;

/// How far the run has come.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Event<'a> {
    /// A dynamic simulation (`command`: the command's text) from `start` to `end` has reached
    /// `time`.
    Integrating {
        command: &'a str,
        start: f64,
        end: f64,
        time: f64,
    },
    /// The analysis that was told about has ended.
    Done,
}

/// What a watcher does with each event.
type Tell = dyn Fn(&Event) + Send + Sync;

/// The watcher of a run (none by default).
#[derive(Clone, Default)]
pub struct Watch(Option<Arc<Tell>>);

impl Watch {
    /// A watcher calling `tell` with every event.
    pub fn new(tell: impl Fn(&Event) + Send + Sync + 'static) -> Watch {
        Watch(Some(Arc::new(tell)))
    }

    /// Tells the watcher, if there is one.
    pub fn tell(&self, event: &Event) {
        if let Some(f) = &self.0 {
            f(event);
        }
    }
}

impl std::fmt::Debug for Watch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.0.is_some() {
            "Watch(..)"
        } else {
            "Watch(none)"
        })
    }
}
