//! A thread that runs until it is told to stop, stopped and joined when its owner is dropped:
//! the hosted server, the computer in a seat and the network session each run on one.

use std::thread::JoinHandle;

use tokio::runtime::Runtime;
use tokio::sync::oneshot;

/// A named thread given a stop signal; dropping this sends the signal and waits for the
/// thread to end.
pub(super) struct BackgroundThread {
    stop: Option<oneshot::Sender<()>>,
    thread: Option<JoinHandle<()>>,
}

impl BackgroundThread {
    /// Starts `body` on a thread called `name`; `body` should end soon after its receiver
    /// fires (or is closed, when this is dropped before the signal could be sent).
    pub(super) fn spawn(
        name: &str,
        body: impl FnOnce(oneshot::Receiver<()>) + Send + 'static,
    ) -> std::io::Result<BackgroundThread> {
        let (stop, stopped) = oneshot::channel();
        let thread = std::thread::Builder::new()
            .name(name.into())
            .spawn(move || body(stopped))?;
        Ok(BackgroundThread {
            stop: Some(stop),
            thread: Some(thread),
        })
    }
}

impl BackgroundThread {
    /// As [`BackgroundThread::spawn`], for a body that needs a current-thread tokio runtime
    /// of its own: `body` is given it, or where none can be made, `no_runtime` is told why.
    pub(super) fn spawn_with_runtime(
        name: &str,
        no_runtime: impl FnOnce(std::io::Error) + Send + 'static,
        body: impl FnOnce(Runtime, oneshot::Receiver<()>) + Send + 'static,
    ) -> std::io::Result<BackgroundThread> {
        BackgroundThread::spawn(name, move |stopped| {
            match tokio::runtime::Builder::new_current_thread()
                .enable_all()
                .build()
            {
                Ok(runtime) => body(runtime, stopped),
                Err(e) => no_runtime(e),
            }
        })
    }
}

impl Drop for BackgroundThread {
    fn drop(&mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;

    #[test]
    fn dropping_it_stops_the_thread_and_waits_for_it() {
        let ended = Arc::new(AtomicBool::new(false));
        let seen = ended.clone();
        let thread = BackgroundThread::spawn("test", move |stopped| {
            let _ = stopped.blocking_recv();
            std::thread::sleep(std::time::Duration::from_millis(20));
            seen.store(true, Ordering::SeqCst);
        })
        .unwrap();
        drop(thread);
        assert!(
            ended.load(Ordering::SeqCst),
            "drop returned before the thread ended"
        );
    }
}
