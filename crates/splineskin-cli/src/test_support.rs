//! What the CLI's unit tests share.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

use tracing::span::{Attributes, Id, Record};
use tracing::subscriber::Interest;
use tracing::{Dispatch, Event, Metadata, Subscriber};

/// A subscriber that asks again at every event: with a count, it counts the library's "reading
/// an SVG document" events (`splineskin_svg::svg_in`); without one, it wants nothing.
///
/// `tracing` decides once per process whether a call site is wanted, and while at most one
/// subscriber is registered it decides by the subscriber of the thread that reaches the call
/// site first. A test on another thread (with no subscriber) reaching the SVG reader first
/// would then switch it off for the counting test too. Kept registered for the life of the
/// test process, the subscriber without a count makes the decision "ask at each event" for
/// every call site, so each event reaches the subscriber of the thread it happens on.
struct CountReadings(Option<Arc<AtomicUsize>>);

impl Subscriber for CountReadings {
    fn register_callsite(&self, _: &'static Metadata<'static>) -> Interest {
        Interest::sometimes()
    }
    fn enabled(&self, _: &Metadata<'_>) -> bool {
        self.0.is_some()
    }
    fn new_span(&self, _: &Attributes<'_>) -> Id {
        Id::from_u64(1)
    }
    fn record(&self, _: &Id, _: &Record<'_>) {}
    fn record_follows_from(&self, _: &Id, _: &Id) {}
    fn event(&self, event: &Event<'_>) {
        let Some(count) = &self.0 else { return };
        let meta = event.metadata();
        if meta.target().starts_with("splineskin_svg::svg_in")
            && meta.fields().field("bytes").is_some()
        {
            count.fetch_add(1, Ordering::Relaxed);
        }
    }
    fn enter(&self, _: &Id) {}
    fn exit(&self, _: &Id) {}
}

static ASK_EVERY_TIME: OnceLock<Dispatch> = OnceLock::new();

/// What `f` returns, and how many SVG documents the library read on this thread meanwhile.
pub fn svg_readings<T>(f: impl FnOnce() -> T) -> (T, usize) {
    ASK_EVERY_TIME.get_or_init(|| Dispatch::new(CountReadings(None)));
    let readings = Arc::new(AtomicUsize::new(0));
    let counting = Dispatch::new(CountReadings(Some(readings.clone())));
    let out = tracing::dispatcher::with_default(&counting, || {
        // Call sites decided before both subscribers were registered are decided again.
        tracing::callsite::rebuild_interest_cache();
        f()
    });
    (out, readings.load(Ordering::Relaxed))
}

#[cfg(test)]
mod tests {
    /// Another thread with no subscriber reaching the SVG reader first (as a test running beside
    /// a counting one does) leaves this thread's readings counted. Run alone, this failed with
    /// the counting subscriber registered by itself (0 readings counted).
    #[test]
    fn readings_count_when_another_thread_reaches_the_reader_first() {
        let (n, readings) = super::svg_readings(|| {
            std::thread::spawn(|| {
                splineskin::drawing::read_svg(splineskin::examples::DEMO_SVG, &Default::default())
                    .unwrap();
            })
            .join()
            .unwrap();
            splineskin::drawing::read_svg(splineskin::examples::DEMO_SVG, &Default::default())
                .unwrap();
            1
        });
        assert_eq!((n, readings), (1, 1));
    }
}
