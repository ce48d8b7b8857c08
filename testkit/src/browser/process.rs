//! Chromium's processes and scratch folder, and making sure both are gone afterwards.
//!
//! Chromium runs in a process group of its own, so its zygotes, renderers and GPU process are
//! stopped with it. Its crash handlers start sessions of their own and escape the group;
//! they are found instead by the scratch folder on their command lines (their crash database
//! is in it), and waited for, so that the folder can be removed.

use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::thread;
use std::time::{Duration, Instant};

use tempfile::TempDir;

pub(crate) struct Process {
    child: Child,
    log: PathBuf,
    stopped: bool,
    /// Last: removed once the processes are gone.
    dir: TempDir,
}

impl Process {
    pub(crate) fn start(mut command: Command, dir: TempDir, log: PathBuf) -> std::io::Result<Self> {
        #[cfg(unix)]
        std::os::unix::process::CommandExt::process_group(&mut command, 0);
        Ok(Process {
            child: command.spawn()?,
            log,
            stopped: false,
            dir,
        })
    }

    pub(crate) fn pid(&self) -> u32 {
        self.child.id()
    }

    pub(crate) fn folder(&self) -> &Path {
        self.dir.path()
    }

    /// The last 4000 bytes of Chromium's standard error.
    pub(crate) fn log_tail(&self) -> String {
        let log = std::fs::read(&self.log).unwrap_or_default();
        let tail = &log[log.len().saturating_sub(4000)..];
        String::from_utf8_lossy(tail).into_owned()
    }

    /// The port and path of the DevTools WebSocket, from the `DevToolsActivePort` file that
    /// Chromium writes into its profile once it listens: the port on the first line, the
    /// path on the second.
    pub(crate) fn devtools_address(
        &mut self,
        profile: &Path,
        deadline: Instant,
    ) -> Result<(u16, String), String> {
        let file = profile.join("DevToolsActivePort");
        loop {
            if let Ok(Some(status)) = self.child.try_wait() {
                return Err(format!("it ended ({status})"));
            }
            // The file may be caught half written: only a whole second line counts.
            if let Ok(text) = std::fs::read_to_string(&file) {
                let mut lines = text.lines();
                let port = lines.next().and_then(|p| p.trim().parse::<u16>().ok());
                let path = lines.next().map(str::trim).unwrap_or("");
                if let Some(port) = port.filter(|&p| p != 0) {
                    // "/devtools/browser/" and a 36-character UUID.
                    if path.starts_with("/devtools/browser/") && path.len() >= 18 + 36 {
                        return Ok((port, path.to_string()));
                    }
                }
            }
            if Instant::now() >= deadline {
                return Err(format!("no complete {} in time", file.display()));
            }
            thread::sleep(Duration::from_millis(20));
        }
    }

    /// Waits up to `grace` for Chromium to end by itself (after it was asked to close), then
    /// stops its process group, and waits for its escaped crash handlers.
    pub(crate) fn stop(&mut self, grace: Duration) {
        if self.stopped {
            return;
        }
        self.stopped = true;
        let deadline = Instant::now() + grace;
        let mut ended = false;
        while !ended && Instant::now() < deadline {
            ended = !matches!(self.child.try_wait(), Ok(None));
            thread::sleep(Duration::from_millis(10));
        }
        stop_group(&mut self.child, ended);
        let folder = self.dir.path().as_os_str().as_encoded_bytes().to_vec();
        // The crash handlers end by themselves about a second after the browser does.
        let deadline = Instant::now() + Duration::from_secs(5);
        while !mentioning(&folder).is_empty() && Instant::now() < deadline {
            thread::sleep(Duration::from_millis(20));
        }
        for pid in mentioning(&folder) {
            kill(pid);
        }
    }
}

impl Drop for Process {
    fn drop(&mut self) {
        self.stop(Duration::ZERO);
    }
}

/// The processes whose command line contains `needle` (read from `/proc`; none elsewhere).
pub(crate) fn mentioning(needle: &[u8]) -> Vec<u32> {
    processes()
        .filter(|pid| {
            std::fs::read(format!("/proc/{pid}/cmdline"))
                .is_ok_and(|cmd| cmd.windows(needle.len()).any(|w| w == needle))
        })
        .collect()
}

/// The processes of process group `group` that have not ended: a zombie, ended but not yet
/// reaped by its parent (often the system's first process, on its own time), does not count.
fn running_in_group(group: u32) -> Vec<u32> {
    processes()
        .filter(|pid| {
            std::fs::read_to_string(format!("/proc/{pid}/stat")).is_ok_and(|stat| {
                // After the name in parentheses (which may hold spaces): state, parent, group.
                let mut fields = stat
                    .rsplit_once(')')
                    .map_or("", |(_, r)| r)
                    .split_whitespace();
                let state = fields.next().unwrap_or("Z");
                let pgrp = fields.nth(1).and_then(|g| g.parse::<u32>().ok());
                pgrp == Some(group) && !matches!(state, "Z" | "X")
            })
        })
        .collect()
}

fn processes() -> impl Iterator<Item = u32> {
    std::fs::read_dir("/proc")
        .into_iter()
        .flatten()
        .filter_map(|e| e.ok()?.file_name().to_str()?.parse::<u32>().ok())
}

/// Asks the group to end (SIGTERM), kills what is left after three seconds (SIGKILL), reaps
/// the main process and waits a moment for the rest to go. Once the main process has `ended`
/// by itself, what is left of the group are child processes on their way out: they are killed at once.
fn stop_group(child: &mut Child, ended: bool) {
    #[cfg(unix)]
    if let Some(pid) = rustix::process::Pid::from_raw(child.id() as i32) {
        use rustix::process::{kill_process_group, Signal};
        let group = child.id();
        let wait_for_group = |child: &mut Child, limit: Duration| {
            let deadline = Instant::now() + limit;
            while !running_in_group(group).is_empty() && Instant::now() < deadline {
                // The main process, once ended, stays in the group until it is reaped.
                let _ = child.try_wait();
                thread::sleep(Duration::from_millis(20));
            }
        };
        if !ended && kill_process_group(pid, Signal::TERM).is_ok() {
            wait_for_group(child, Duration::from_secs(3));
        }
        let _ = kill_process_group(pid, Signal::KILL);
        let _ = child.kill();
        let _ = child.wait();
        wait_for_group(child, Duration::from_secs(2));
    }
    #[cfg(not(unix))]
    {
        let _ = ended;
        let _ = child.kill();
        let _ = child.wait();
    }
}

fn kill(pid: u32) {
    #[cfg(unix)]
    if let Some(pid) = rustix::process::Pid::from_raw(pid as i32) {
        let _ = rustix::process::kill_process(pid, rustix::process::Signal::KILL);
    }
    #[cfg(not(unix))]
    let _ = pid;
}
