//! Fits run most promising first on every thread, until one settles the recording.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Duration;

/// `job` on each of `items`, in their order, as many at once as the pool has threads; once a
/// result is `done` no later item starts, and those running are stopped (their own flag, which
/// `job` gets as its cancel). Returns the results up to and including the first done item in
/// `items`' order (all of them where none is): the same whatever the thread count and
/// whichever thread finished first, so the answer does not depend on the machine. A queue, not
/// batches of two: a batch waits for its slowest fit (slip's runs take several times a drag's),
/// while here the other thread takes the next item.
///
/// The caller's `cancel` reaches every running job within [`WATCH`]. Where it is set, some
/// results may be missing or be the jobs' own cancellation: the caller checks `cancel`.
pub(super) fn in_order_until<T: Sync, R: Send>(
    items: &[T],
    job: &(dyn Fn(&T, &AtomicBool) -> R + Sync),
    done: &(dyn Fn(&R) -> bool + Sync),
    cancel: &AtomicBool,
) -> Vec<R> {
    let stops: Vec<AtomicBool> = items.iter().map(|_| AtomicBool::new(false)).collect();
    let results: Vec<Mutex<Option<R>>> = items.iter().map(|_| Mutex::new(None)).collect();
    let next = AtomicUsize::new(0);
    let first_done = AtomicUsize::new(usize::MAX);
    let finished = AtomicBool::new(false);
    let worker = || {
        loop {
            let i = next.fetch_add(1, Ordering::SeqCst);
            if i >= items.len() || i > first_done.load(Ordering::SeqCst) {
                break;
            }
            let r = job(&items[i], &stops[i]);
            if done(&r) {
                first_done.fetch_min(i, Ordering::SeqCst);
                stops[i + 1..].iter().for_each(|s| s.store(true, Ordering::SeqCst));
            }
            *results[i].lock().unwrap_or_else(|e| e.into_inner()) = Some(r);
        }
    };
    std::thread::scope(|scope| {
        // The caller's cancel handed on to each job's own flag.
        scope.spawn(|| {
            while !finished.load(Ordering::SeqCst) {
                if cancel.load(Ordering::Relaxed) {
                    stops.iter().for_each(|s| s.store(true, Ordering::SeqCst));
                }
                std::thread::sleep(WATCH);
            }
        });
        let threads = rayon::current_num_threads().clamp(1, items.len().max(1));
        rayon::scope(|s| {
            for _ in 0..threads {
                s.spawn(|_| worker());
            }
        });
        finished.store(true, Ordering::SeqCst);
    });
    let keep = first_done.load(Ordering::SeqCst).saturating_add(1).min(items.len());
    results
        .into_iter()
        .take(keep)
        .filter_map(|m| m.into_inner().unwrap_or_else(|e| e.into_inner()))
        .collect()
}

/// How often the caller's cancel is looked at.
const WATCH: Duration = Duration::from_millis(20);

#[cfg(test)]
mod tests {
    use super::*;

    fn slow_square(x: &u64, stop: &AtomicBool) -> Option<u64> {
        // Later items finish first, so a result that depended on timing would show.
        for _ in 0..(20 - x) {
            if stop.load(Ordering::SeqCst) {
                return None;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
        Some(x * x)
    }

    #[test]
    fn the_results_end_at_the_first_item_done_in_order_whoever_finishes_first() {
        let items: Vec<u64> = (0..10).collect();
        let done = |r: &Option<u64>| r.is_some_and(|v| v >= 9);
        let never = AtomicBool::new(false);
        for _ in 0..5 {
            let out = in_order_until(&items, &slow_square, &done, &never);
            assert_eq!(out, vec![Some(0), Some(1), Some(4), Some(9)]);
        }
    }

    #[test]
    fn with_nothing_done_every_item_runs() {
        let items: Vec<u64> = (0..7).collect();
        let never = AtomicBool::new(false);
        let out = in_order_until(&items, &slow_square, &|_| false, &never);
        assert_eq!(out, items.iter().map(|x| Some(x * x)).collect::<Vec<_>>());
    }

    #[test]
    fn the_callers_cancel_stops_the_running_jobs() {
        // Each job would run for a second unless stopped.
        let long = |_: &u64, stop: &AtomicBool| {
            for _ in 0..500 {
                if stop.load(Ordering::SeqCst) {
                    return None;
                }
                std::thread::sleep(Duration::from_millis(2));
            }
            Some(())
        };
        let items: Vec<u64> = vec![0; 4];
        let cancel = AtomicBool::new(true);
        let out = in_order_until(&items, &long, &|_| false, &cancel);
        assert_eq!(out, vec![None; 4]);
    }
}
