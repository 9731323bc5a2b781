//! What the CLI's unit tests share.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use tracing::span::{Attributes, Id, Record};
use tracing::{Event, Metadata, Subscriber};

/// Counts the library's "reading an SVG document" events (`splineskin_svg::svg_in`).
struct CountReadings(Arc<AtomicUsize>);

impl Subscriber for CountReadings {
    fn enabled(&self, _: &Metadata<'_>) -> bool {
        true
    }
    fn new_span(&self, _: &Attributes<'_>) -> Id {
        Id::from_u64(1)
    }
    fn record(&self, _: &Id, _: &Record<'_>) {}
    fn record_follows_from(&self, _: &Id, _: &Id) {}
    fn event(&self, event: &Event<'_>) {
        let meta = event.metadata();
        if meta.target().starts_with("splineskin_svg::svg_in")
            && meta.fields().field("bytes").is_some()
        {
            self.0.fetch_add(1, Ordering::Relaxed);
        }
    }
    fn enter(&self, _: &Id) {}
    fn exit(&self, _: &Id) {}
}

/// What `f` returns, and how many SVG documents the library read on this thread meanwhile.
pub fn svg_readings<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let readings = Arc::new(AtomicUsize::new(0));
    let out = tracing::subscriber::with_default(CountReadings(readings.clone()), f);
    (out, readings.load(Ordering::Relaxed))
}
