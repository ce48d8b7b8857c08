//! The threads that run rooms' work (see [`crate::work`]): a fixed number of plain threads
//! taking jobs from one queue. Ordering within a room is the hub's business (a room is out
//! on at most one job at a time); the pool only makes sure that while one room's shot is
//! being simulated, the other threads keep taking other rooms' jobs.

use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;

type Job = Box<dyn FnOnce() + Send>;

/// Worker threads (`room-worker-N`) taking jobs from one queue; dropping it finishes the jobs
/// already queued, then stops them.
pub struct Pool {
    jobs: Option<Sender<Job>>,
    threads: Vec<JoinHandle<()>>,
}

/// One thread per core, and at least two, so that one long job never stops the rest.
pub fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(2, |n| n.get().max(2))
}

impl Pool {
    /// Starts `threads` workers, at least one. A thread the system refuses to start is left
    /// out with a warning; if none starts, rooms could never run, so that is an error.
    pub fn new(threads: usize) -> std::io::Result<Pool> {
        let (tx, rx) = mpsc::channel::<Job>();
        let rx = Arc::new(Mutex::new(rx));
        let mut started = Vec::new();
        let mut refused = None;
        for i in 0..threads.max(1) {
            let rx = rx.clone();
            match std::thread::Builder::new()
                .name(format!("room-worker-{i}"))
                .spawn(move || work(&rx))
            {
                Ok(t) => started.push(t),
                Err(e) => {
                    tracing::warn!(error = %e, "a room worker thread did not start");
                    refused = Some(e);
                }
            }
        }
        match (started.is_empty(), refused) {
            (true, Some(e)) => Err(e),
            _ => Ok(Pool {
                jobs: Some(tx),
                threads: started,
            }),
        }
    }

    /// Queues `job` for the next free thread; jobs start in the order they were queued.
    pub fn run(&self, job: impl FnOnce() + Send + 'static) {
        if let Some(jobs) = &self.jobs {
            // The threads only stop once `jobs` is dropped, so the send cannot fail.
            let _ = jobs.send(Box::new(job));
        }
    }
}

fn work(jobs: &Mutex<Receiver<Job>>) {
    loop {
        // The lock is released before the job runs.
        let job = jobs.lock().unwrap_or_else(PoisonError::into_inner).recv();
        match job {
            Ok(job) => job(),
            Err(_) => return,
        }
    }
}

impl Drop for Pool {
    /// Finishes every job already queued, then stops the threads.
    fn drop(&mut self) {
        self.jobs = None;
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;

    const BOUND: Duration = Duration::from_secs(10);

    #[test]
    fn a_job_that_does_not_finish_does_not_stop_the_next() {
        let pool = Pool::new(2).expect("threads");
        let (release_tx, release_rx) = mpsc::channel::<()>();
        let (events_tx, events_rx) = mpsc::channel::<&str>();
        let events = events_tx.clone();
        pool.run(move || {
            events.send("slow started").unwrap();
            // Held until the test lets it go (bounded, so a failing test cannot hang).
            let _ = release_rx.recv_timeout(BOUND);
            events.send("slow done").unwrap();
        });
        assert_eq!(events_rx.recv_timeout(BOUND), Ok("slow started"));
        let events = events_tx.clone();
        pool.run(move || events.send("quick done").unwrap());
        assert_eq!(events_rx.recv_timeout(BOUND), Ok("quick done"));
        release_tx.send(()).unwrap();
        assert_eq!(events_rx.recv_timeout(BOUND), Ok("slow done"));
    }

    #[test]
    fn dropping_the_pool_finishes_the_queued_jobs() {
        let (tx, rx) = mpsc::channel();
        let pool = Pool::new(1).expect("a thread");
        for i in 0..5 {
            let tx = tx.clone();
            pool.run(move || tx.send(i).unwrap());
        }
        drop(pool);
        assert_eq!(rx.try_iter().collect::<Vec<_>>(), vec![0, 1, 2, 3, 4]);
    }
}
