//! Closing the game does not give it away: real processes (the client core the window
//! uses, in `breakshot-seat`), killed and started again with the same data directory.
//! A joiner killed mid-game and started again with the same invite is back in its seat; a
//! host killed and started again is back in the same room with the same invite, and the
//! joiner that kept running reconnects to it.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{self, Receiver};
use std::time::Instant;

use breakshot_tests::{scratch, PATIENCE};

/// A running `breakshot-seat`, killed when dropped.
struct Player {
    name: &'static str,
    child: Child,
    lines: Receiver<String>,
}

impl Player {
    fn start(name: &'static str, args: &[&str]) -> Player {
        let mut child = Command::new(env!("CARGO_BIN_EXE_breakshot-seat"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("start breakshot-seat");
        let out = child.stdout.take().expect("piped stdout");
        let (tx, lines) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(out).lines().map_while(Result::ok) {
                if tx.send(line).is_err() {
                    return;
                }
            }
        });
        Player { name, child, lines }
    }

    /// The first line (from now on) that `want` accepts; fails after [`PATIENCE`].
    fn expect(&mut self, what: &str, want: impl Fn(&str) -> bool) -> String {
        let until = Instant::now() + PATIENCE;
        loop {
            let left = until.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) if want(&line) => return line,
                Ok(_) => {}
                Err(_) => panic!("{} never printed {what}", self.name),
            }
        }
    }

    /// The turn of a `started seat S turn N` line for `seat`.
    fn started(&mut self, seat: &str) -> u32 {
        let prefix = format!("started seat Some({seat}) turn ");
        let line = self.expect(&format!("a game seated in {seat}"), |l| {
            l.starts_with(&prefix)
        });
        line[prefix.len()..].parse().expect("a turn number")
    }

    fn kill(mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Player {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A UDP port free on loopback now (the host is restarted on the same port, so the invite
/// stays the same).
fn free_port() -> u16 {
    let socket = std::net::UdpSocket::bind("127.0.0.1:0").expect("bind a UDP socket");
    socket.local_addr().expect("local address").port()
}

#[test]
fn killed_players_come_back_to_their_seats_in_the_same_game() {
    let host_data = scratch("resume-host");
    let guest_data = scratch("resume-guest");
    let port = free_port().to_string();
    let host_dir = host_data.path().to_str().expect("a UTF-8 path").to_string();
    let guest_dir = guest_data
        .path()
        .to_str()
        .expect("a UTF-8 path")
        .to_string();

    let mut host = Player::start("the host", &["host", &host_dir, &port]);
    let invite_line = host.expect("its invite", |l| l.starts_with("invite "));
    let invite = invite_line["invite ".len()..].to_string();
    assert_eq!(
        host.expect("whether it resumed", |l| l.starts_with("resumed")),
        "resumed false"
    );

    let mut guest = Player::start("the guest", &["join", &guest_dir, &invite]);
    assert_eq!(guest.started("B"), 0);
    host.expect("its break", |l| l == "shot");
    guest.expect("the break's verdict", |l| l.starts_with("judged"));

    // The guest's process dies; the same command puts it back in seat B of the same game.
    guest.kill();
    let mut guest = Player::start("the restarted guest", &["join", &guest_dir, &invite]);
    assert!(
        guest.started("B") >= 1,
        "the guest is back in the game after the break"
    );
    host.expect("the guest back", |l| l == "connection Connected");

    // The host's process dies; started again with the same data directory it takes its
    // game back (same invite), and the guest that kept running reconnects to it.
    host.kill();
    guest.expect("the host gone", |l| l == "connection Reconnecting");
    let mut host = Player::start("the restarted host", &["host", &host_dir, &port]);
    assert_eq!(
        host.expect("its invite", |l| l.starts_with("invite ")),
        invite_line
    );
    assert_eq!(
        host.expect("whether it resumed", |l| l.starts_with("resumed")),
        "resumed true"
    );
    assert!(
        host.started("A") >= 1,
        "the host is back in the game after the break"
    );
    assert!(
        guest.started("B") >= 1,
        "the guest is back in the same game"
    );
    host.expect("the guest there", |l| l == "connection Connected");

    drop((host, guest));
    let left: Vec<_> = std::fs::read_dir(guest_data.path().join("seats"))
        .expect("the guest's seats")
        .flatten()
        .collect();
    assert_eq!(left.len(), 1, "one seat remembered by the guest");
}
