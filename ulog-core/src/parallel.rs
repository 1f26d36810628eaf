//! The work queue that spreads jobs over threads: the columnar load and the Parquet
//! export use it for topics, the `ulog` command line for topics and for logs; and
//! [`Shares`], the topics of one log shared between passes on several threads.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

/// Runs `job(i)` for every `i` in `0..costs.len()` on up to `threads` threads (the
/// calling one among them), each thread taking the next job from a shared queue,
/// largest `costs` first so that the threads end together. After a job returns
/// `Err`, no new job is started.
///
/// Returns each job's result at its index (`None`: not started, because a job failed
/// first). A panic in a job is passed on.
///
/// ```
/// let sizes = [3u64, 10, 1, 7];
/// let done = ulog_core::parallel::largest_first(&sizes, 2, |i| {
///     if sizes[i] > 100 { Err("too large") } else { Ok(sizes[i] * 2) }
/// });
/// let doubled: Vec<u64> = done.into_iter().map(|r| r.unwrap().unwrap()).collect();
/// assert_eq!(doubled, [6, 20, 2, 14]);
/// ```
pub fn largest_first<T, E, F>(costs: &[u64], threads: usize, job: F) -> Vec<Option<Result<T, E>>>
where
    T: Send,
    E: Send,
    F: Fn(usize) -> Result<T, E> + Sync,
{
    let mut order: Vec<usize> = (0..costs.len()).collect();
    // Ties in index order: the same jobs start first from run to run.
    order.sort_by_key(|&i| (core::cmp::Reverse(costs[i]), i));
    let next = AtomicUsize::new(0);
    let failed = AtomicBool::new(false);
    let results: Mutex<Vec<Option<Result<T, E>>>> =
        Mutex::new((0..costs.len()).map(|_| None).collect());
    let work = || loop {
        if failed.load(Ordering::Relaxed) {
            break;
        }
        let Some(&i) = order.get(next.fetch_add(1, Ordering::Relaxed)) else {
            break;
        };
        let result = job(i);
        if result.is_err() {
            failed.store(true, Ordering::Relaxed);
        }
        // A panic elsewhere poisons the lock only while that thread unwinds, and the
        // scope passes the panic on: the results are complete either way.
        results.lock().unwrap_or_else(|p| p.into_inner())[i] = Some(result);
    };
    let threads = threads.clamp(1, costs.len().max(1));
    if threads == 1 {
        work();
    } else {
        std::thread::scope(|s| {
            let helpers: Vec<_> = (1..threads).map(|_| s.spawn(work)).collect();
            work();
            join_all(helpers);
        });
    }
    results.into_inner().unwrap_or_else(|p| p.into_inner())
}

/// Joins scoped threads explicitly, passing a panic on. The scope's own join returns
/// once each thread's closure has, before its thread-local destructors have run
/// (rust-lang/rust#116179): a caller would find our threads still alive after the
/// call, and a leak checker finds their destructor lists unfreed.
pub(crate) fn join_all<T>(handles: Vec<std::thread::ScopedJoinHandle<'_, T>>) -> Vec<T> {
    handles
        .into_iter()
        .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::largest_first;

    #[test]
    fn every_job_runs_once_on_any_number_of_threads() {
        let costs: Vec<u64> = (0..50).map(|i| (i * 37) % 11).collect();
        for threads in [0, 1, 2, 3, 64] {
            let ran = std::sync::atomic::AtomicUsize::new(0);
            let results = largest_first(&costs, threads, |i| {
                ran.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                Ok::<usize, ()>(i)
            });
            let got: Vec<usize> = results.into_iter().map(|r| r.unwrap().unwrap()).collect();
            assert_eq!(got, (0..50).collect::<Vec<_>>(), "{threads} threads");
            assert_eq!(ran.into_inner(), 50);
        }
    }

    #[test]
    fn no_job_starts_after_one_fails() {
        // One thread: the largest job runs first and fails; nothing else starts.
        let results = largest_first(&[1, 9, 5], 1, |i| if i == 1 { Err(i) } else { Ok(i) });
        assert_eq!(results, [None, Some(Err(1)), None]);
    }
}

/// Which of several passes over one log takes which subscription (topic instance):
/// each pass frames the whole log and handles its share of the topics. Every pass
/// keeps its own copy and, meeting the same subscriptions in the same order, takes
/// the same decisions, so that each subscription has exactly one owner. The columnar
/// load and the Python package's reader use it.
///
/// ```
/// use ulog_core::parallel::Shares;
/// // The work of subscriptions 0..3 in a sample of the log.
/// let mut a = Shares::new(&[10, 70, 30], 2);
/// let mut b = a.clone();
/// assert_eq!(a.owner(1), 0); // the largest first, to the first share
/// assert_eq!((a.owner(0), a.owner(2)), (1, 1));
/// // A subscription not in the sample gets the typical weight, the same in every copy.
/// assert_eq!(a.owner(7), b.owner(7));
/// ```
#[derive(Debug, Clone)]
pub struct Shares {
    owner: Vec<Option<usize>>,
    load: Vec<u64>,
    /// The weight given to a subscription first met after the sample.
    typical: u64,
}

impl Shares {
    /// Shares balanced by the work of each subscription in the sample, largest
    /// first, each to the least loaded share.
    /// (`threads`: at least 1.)
    pub fn new(work: &[u64], threads: usize) -> Shares {
        let threads = threads.max(1);
        let mut shares = Shares {
            owner: vec![None; work.len()],
            load: vec![0; threads],
            typical: 0,
        };
        let mut order: Vec<usize> = (0..work.len()).collect();
        order.sort_by_key(|&i| (core::cmp::Reverse(work[i]), i));
        for i in order {
            shares.assign(i, work[i]);
        }
        let total: u64 = work.iter().sum();
        shares.typical = total / work.len().max(1) as u64;
        shares
    }

    fn assign(&mut self, sub: usize, weight: u64) -> usize {
        let least = (0..self.load.len())
            .min_by_key(|&k| (self.load[k], k))
            .expect("at least one share");
        self.load[least] += weight;
        if sub >= self.owner.len() {
            self.owner.resize(sub + 1, None);
        }
        self.owner[sub] = Some(least);
        least
    }

    /// The share that handles subscription `sub` (by its index); one first met now
    /// goes to the least loaded share.
    #[inline]
    pub fn owner(&mut self, sub: usize) -> usize {
        match self.owner.get(sub) {
            Some(&Some(k)) => k,
            _ => self.assign(sub, self.typical),
        }
    }
}
