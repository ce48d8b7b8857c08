//! What the project's tests share: running a program with a deadline, so that a test that
//! cannot finish fails with a message instead of hanging, and scratch folders that are removed
//! when dropped, also when the test fails; and a headless browser for the web client's tests
//! ([`browser`]).

#![warn(missing_docs, unreachable_pub)]

use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, Command, Output, Stdio};
use std::sync::mpsc;
use std::thread;
use std::time::{Duration, Instant};

pub mod browser;
pub mod web;

pub use tempfile::TempDir;

/// A fresh folder under the system's temporary directory, its name starting with
/// `breakshot-NAME-`; it and everything in it are removed when it is dropped.
pub fn scratch(name: &str) -> TempDir {
    tempfile::Builder::new()
        .prefix(&format!("breakshot-{name}-"))
        .tempdir()
        .expect("a scratch folder")
}

/// Runs `command` to its end, writing `stdin` to it (or giving it none), and returns what it
/// printed and how it ended. Fails the test, after killing the program and everything it
/// started, if it has not ended within `limit`.
///
/// The program runs in a process group of its own, so that a wrapper such as `xvfb-run` is
/// stopped with the programs it started; anything the program left running when it ended is
/// stopped too. Its output is read while it runs, so a program that prints more than a pipe
/// holds cannot block against the wait.
pub fn run(command: &mut Command, stdin: Option<&[u8]>, limit: Duration) -> Output {
    let mut child = spawn_in_group(command, stdin.is_some());
    let name = format!("{:?}", command.get_program());
    let writer = stdin.map(|bytes| {
        let mut pipe = child.stdin.take().expect("a piped stdin");
        let bytes = bytes.to_vec();
        // A program may refuse its arguments and end before reading: a broken pipe is
        // how that shows, and is no failure of the test.
        thread::spawn(move || match pipe.write_all(&bytes) {
            Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e),
            _ => Ok(()),
        })
    });
    let stdout = drain(child.stdout.take().expect("a piped stdout"));
    let stderr = drain(child.stderr.take().expect("a piped stderr"));

    let deadline = Instant::now() + limit;
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break status,
            Ok(None) if Instant::now() < deadline => thread::sleep(Duration::from_millis(10)),
            Ok(None) => {
                stop_group(&mut child);
                let err = stderr
                    .recv_timeout(Duration::from_secs(5))
                    .unwrap_or_default();
                panic!(
                    "{name} did not finish within {limit:?}; it was stopped. Its errors:\n{}",
                    String::from_utf8_lossy(&err)
                );
            }
            Err(e) => {
                stop_group(&mut child);
                panic!("waiting for {name}: {e}");
            }
        }
    };
    // Whatever it started and left running (an X server, a server it hosted) goes with it.
    kill_group(&mut child);
    if let Some(writer) = writer {
        if let Ok(Err(e)) = writer.join() {
            panic!("writing to {name}: {e}");
        }
    }
    let collect = |rx: mpsc::Receiver<Vec<u8>>, what: &str| {
        rx.recv_timeout(Duration::from_secs(10))
            .unwrap_or_else(|_| panic!("{name}'s {what} was not closed 10 s after it ended"))
    };
    Output {
        status,
        stdout: collect(stdout, "standard output"),
        stderr: collect(stderr, "standard error"),
    }
}

/// [`run`] for a program that must succeed: its output, or the test fails with `failure`,
/// how the program ended and everything it printed.
pub fn run_ok(
    command: &mut Command,
    stdin: Option<&[u8]>,
    limit: Duration,
    failure: &str,
) -> Output {
    let out = run(command, stdin, limit);
    assert!(
        out.status.success(),
        "{failure} ({}):\n{}{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// A program started with [`Spawned::start`]: it and everything it started are killed when
/// this is dropped, so a failing test leaves no process behind.
pub struct Spawned {
    child: Child,
}

impl Spawned {
    /// Starts `command` in a process group of its own, with no standard input.
    pub fn start(command: &mut Command) -> Spawned {
        command.stdin(Stdio::null());
        Spawned {
            child: spawn_group(command),
        }
    }

    /// The running program, to read its pipes or send it signals.
    pub fn child(&mut self) -> &mut Child {
        &mut self.child
    }

    /// Sends the program SIGINT, as Ctrl-C in a terminal does.
    #[cfg(unix)]
    pub fn interrupt(&self) {
        if let Some(pid) = rustix::process::Pid::from_raw(self.child.id() as i32) {
            rustix::process::kill_process(pid, rustix::process::Signal::INT)
                .expect("the program takes a signal");
        }
    }

    /// Sends the program SIGTERM, as a service manager stopping it does.
    #[cfg(unix)]
    pub fn terminate(&self) {
        if let Some(pid) = rustix::process::Pid::from_raw(self.child.id() as i32) {
            rustix::process::kill_process(pid, rustix::process::Signal::TERM)
                .expect("the program takes a signal");
        }
    }

    /// Waits up to `limit` for the program to end by itself and returns how it ended; fails
    /// the test, after killing it, if it has not.
    pub fn wait(&mut self, limit: Duration) -> std::process::ExitStatus {
        let deadline = Instant::now() + limit;
        loop {
            match self.child.try_wait() {
                Ok(Some(status)) => return status,
                Ok(None) if Instant::now() < deadline => thread::sleep(Duration::from_millis(10)),
                Ok(None) => {
                    stop_group(&mut self.child);
                    panic!(
                        "{:?} did not end within {limit:?}; it was stopped",
                        self.child
                    );
                }
                Err(e) => panic!("waiting for a child process: {e}"),
            }
        }
    }
}

/// Reads one line from `pipe` (a child's output) and hands back the rest of it for later
/// reads; fails the test if no whole line has come within `limit`.
pub fn read_line<R: Read + Send + 'static>(pipe: R, limit: Duration) -> (String, BufReader<R>) {
    let (tx, rx) = mpsc::channel();
    thread::spawn(move || {
        let mut reader = BufReader::new(pipe);
        let mut line = String::new();
        let read = reader.read_line(&mut line);
        let _ = tx.send(read.map(|_| (line, reader)));
    });
    match rx.recv_timeout(limit) {
        Ok(Ok((line, reader))) => (line, reader),
        Ok(Err(e)) => panic!("reading a line from a child process: {e}"),
        Err(_) => panic!("no line from the child process within {limit:?}"),
    }
}

impl Drop for Spawned {
    fn drop(&mut self) {
        stop_group(&mut self.child);
    }
}

fn spawn_in_group(command: &mut Command, piped_stdin: bool) -> Child {
    command
        .stdin(if piped_stdin {
            Stdio::piped()
        } else {
            Stdio::null()
        })
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    spawn_group(command)
}

fn spawn_group(command: &mut Command) -> Child {
    #[cfg(unix)]
    std::os::unix::process::CommandExt::process_group(command, 0);
    command
        .spawn()
        .unwrap_or_else(|e| panic!("starting {:?}: {e}", command.get_program()))
}

/// Reads a pipe to its end on a thread of its own; the bytes arrive when it closes.
fn drain(mut pipe: impl Read + Send + 'static) -> mpsc::Receiver<Vec<u8>> {
    let (tx, rx) = mpsc::channel();
    thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = pipe.read_to_end(&mut bytes);
        let _ = tx.send(bytes);
    });
    rx
}

/// Kills the program's whole process group and reaps the program.
/// Stops the program's whole process group and reaps the program.
fn stop_group(child: &mut Child) {
    kill_group(child);
    let _ = child.kill();
    let _ = child.wait();
}

/// Stops what is left of the program's process group: first asked to end (SIGTERM), so an X
/// server removes its lock file, then killed if it has not gone within a few seconds.
fn kill_group(child: &mut Child) {
    #[cfg(unix)]
    if let Some(pid) = rustix::process::Pid::from_raw(child.id() as i32) {
        use rustix::process::{kill_process_group, test_kill_process_group, Signal};
        if kill_process_group(pid, Signal::TERM).is_err() {
            return; // nothing left in the group
        }
        let deadline = Instant::now() + Duration::from_secs(5);
        while test_kill_process_group(pid).is_ok() && Instant::now() < deadline {
            // The program itself, once ended, stays in the group until it is reaped.
            let _ = child.try_wait();
            thread::sleep(Duration::from_millis(10));
        }
        let _ = kill_process_group(pid, Signal::KILL);
    }
    #[cfg(not(unix))]
    let _ = child;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The message of the panic `f` must end in (what a failing test says).
    pub(crate) fn panic_message<R>(f: impl FnOnce() -> R + std::panic::UnwindSafe) -> String {
        let failed = std::panic::catch_unwind(f).map(drop);
        let message = failed.expect_err("it fails");
        message.downcast_ref::<String>().expect("a message").clone()
    }

    #[test]
    fn a_program_that_ends_gives_its_output_and_status() {
        let out = run(
            Command::new("sh").args(["-c", "cat; echo done >&2; exit 3"]),
            Some(b"hello"),
            Duration::from_secs(30),
        );
        assert_eq!(out.stdout, b"hello");
        assert_eq!(out.stderr, b"done\n");
        assert_eq!(out.status.code(), Some(3));
    }

    #[test]
    fn a_program_that_must_succeed_gives_its_output_or_fails_the_test_saying_why() {
        let limit = Duration::from_secs(30);
        let sh = |script: &str| {
            let mut command = Command::new("sh");
            command.args(["-c", script]);
            command
        };
        let out = run_ok(&mut sh("echo fine"), None, limit, "echo failed");
        assert_eq!(out.stdout, b"fine\n");
        let mut failing = sh("echo said; echo why >&2; exit 3");
        // A Command holds no state a panic could leave half-changed.
        let message = panic_message(std::panic::AssertUnwindSafe(move || {
            run_ok(&mut failing, None, limit, "the shell failed")
        }));
        assert!(message.starts_with("the shell failed ("), "{message}");
        assert!(message.ends_with("said\nwhy\n"), "{message}");
    }

    #[test]
    fn output_larger_than_a_pipe_does_not_block_the_wait() {
        let out = run(
            Command::new("sh").args(["-c", "head -c 1000000 /dev/zero"]),
            None,
            Duration::from_secs(30),
        );
        assert_eq!(out.stdout.len(), 1_000_000);
    }

    #[test]
    fn a_program_that_does_not_end_fails_the_test_and_is_stopped() {
        let message = panic_message(|| {
            // The shell's child keeps the pipes open: the whole group must be stopped.
            run(
                Command::new("sh").args(["-c", "sleep 600 & wait"]),
                None,
                Duration::from_millis(300),
            )
        });
        assert!(message.contains("did not finish within"), "{message}");
    }

    #[test]
    fn a_scratch_folder_is_removed_when_dropped() {
        let dir = scratch("kit");
        let path = dir.path().to_path_buf();
        std::fs::write(path.join("file"), b"x").expect("write");
        assert!(path.starts_with(std::env::temp_dir()));
        drop(dir);
        assert!(!path.exists());
    }

    #[test]
    fn a_spawned_program_is_killed_when_dropped() {
        let mut spawned = Spawned::start(Command::new("sleep").arg("600"));
        let pid = spawned.child().id();
        drop(spawned);
        let alive = run(
            Command::new("kill").args(["-0", &pid.to_string()]),
            None,
            Duration::from_secs(30),
        );
        assert!(!alive.status.success(), "the program still runs");
    }
}
