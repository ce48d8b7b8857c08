//! A real `breakshot` window whose `report: ...` lines (standard error, `BREAKSHOT_REPORT=1`)
//! are collected as it runs, so a test can wait for what the window says while acting on it.
#![allow(dead_code)] // not every test file uses every part

use std::io::{BufRead, BufReader, Read};
use std::process::{Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use breakshot_shared::protocol::Invite;
use breakshot_testkit::Spawned;

/// A window process and what it has reported so far.
pub struct Reported {
    pub process: Spawned,
    said: Arc<Mutex<Vec<String>>>,
}

impl Reported {
    /// Starts `command` with its reports on; its standard output is read (and dropped) so it
    /// never blocks on a full pipe.
    pub fn start(command: &mut Command) -> Reported {
        Reported::start_reading(command, |out| {
            std::thread::spawn(move || std::io::copy(&mut { out }, &mut std::io::sink()));
        })
    }

    /// Starts `command` (a `breakshot host`) and reads the invite it prints first.
    pub fn host(command: &mut Command) -> (Reported, Invite) {
        let mut invite = None;
        let window = Reported::start_reading(command, |out| {
            let (line, rest) = breakshot_testkit::read_line(out, Duration::from_secs(60));
            invite = Some(line.trim().parse().expect("the invite is the first line"));
            std::thread::spawn(move || std::io::copy(&mut { rest }, &mut std::io::sink()));
        });
        (window, invite.expect("read above"))
    }

    fn start_reading(
        command: &mut Command,
        stdout: impl FnOnce(std::process::ChildStdout),
    ) -> Reported {
        let mut process = Spawned::start(
            command
                .env("BREAKSHOT_REPORT", "1")
                .stdout(Stdio::piped())
                .stderr(Stdio::piped()),
        );
        let out = process.child().stdout.take().expect("the window's output");
        let err = process.child().stderr.take().expect("the window's reports");
        let said = Arc::new(Mutex::new(Vec::new()));
        let heard = said.clone();
        std::thread::spawn(move || collect(err, &heard));
        stdout(out);
        Reported { process, said }
    }

    /// The report lines so far, without their `report: ` prefix.
    pub fn said(&self) -> Vec<String> {
        self.said.lock().expect("the reports").clone()
    }

    /// The first report line after the first `after` of them for which `want` holds, waited
    /// for at most `limit`; fails the test naming `what` (and what was said) if none came.
    pub fn wait_for(
        &self,
        after: usize,
        limit: Duration,
        what: &str,
        want: impl Fn(&str) -> bool,
    ) -> (usize, String) {
        let deadline = Instant::now() + limit;
        loop {
            let said = self.said();
            if let Some((i, line)) = said.iter().enumerate().skip(after).find(|(_, l)| want(l)) {
                return (i, line.clone());
            }
            assert!(
                Instant::now() < deadline,
                "{what}: not reported within {limit:?}: {said:?}"
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }
}

/// Keeps the `report: ` lines of `stream` in `said` until it ends.
fn collect(stream: impl Read, said: &Mutex<Vec<String>>) {
    for line in BufReader::new(stream).lines().map_while(Result::ok) {
        if let Some(report) = line.strip_prefix("report: ") {
            said.lock().expect("the reports").push(report.to_owned());
        }
    }
}
