//! A player without a window, for tests that start, kill and restart real processes: hosts
//! (`breakshot-seat host DATA PORT`) or joins (`breakshot-seat join DATA INVITE`) through the
//! same client core the game window uses (`Host`, `NetLink`, the seat store in DATA), and
//! prints one line per thing a player would see. The host breaks once the opponent is there.
//! Exits by itself after a minute and a half, so a test that dies leaves nothing running.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use breakshot_client::net::{Host, HostOptions, NetLink, SeatStore};
use breakshot_client::play::{GameEvent, GameLink};
use breakshot_client::view::hud::Connection;
use breakshot_shared::protocol::{ClientMessage, Invite};
use breakshot_shared::rules::Command;
use breakshot_tests::break_shot;

const LIFETIME: Duration = Duration::from_secs(90);

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (mut link, hosting): (Box<dyn GameLink>, bool) = match args.as_slice() {
        [what, data, port] if what == "host" => {
            let Ok(port) = port.parse::<u16>() else {
                eprintln!("breakshot-seat: {port:?} is not a port");
                return ExitCode::from(2);
            };
            let options = HostOptions {
                bind: SocketAddr::from(([127, 0, 0, 1], port)),
                ..HostOptions::new(PathBuf::from(data))
            };
            match Host::start(&options) {
                Ok(host) => {
                    println!("invite {}", host.invite());
                    println!("resumed {}", host.resumed());
                    (Box::new(host), true)
                }
                Err(e) => {
                    eprintln!("breakshot-seat: {e}");
                    return ExitCode::FAILURE;
                }
            }
        }
        [what, data, invite] if what == "join" => {
            let Ok(invite) = invite.parse::<Invite>() else {
                eprintln!("breakshot-seat: {invite:?} is not an invite");
                return ExitCode::from(2);
            };
            let seats = SeatStore::new(&PathBuf::from(data));
            match NetLink::join(invite, "guest", Some(seats)) {
                Ok(link) => (Box::new(link), false),
                Err(e) => {
                    eprintln!("breakshot-seat: {e}");
                    return ExitCode::FAILURE;
                }
            }
        }
        _ => {
            eprintln!("usage: breakshot-seat host DATA PORT | breakshot-seat join DATA INVITE");
            return ExitCode::from(2);
        }
    };
    let since = Instant::now();
    let mut game = None;
    let mut opponent_here = false;
    let mut broke = false;
    while since.elapsed() < LIFETIME {
        while let Some(event) = link.poll() {
            match event {
                GameEvent::Started(g) => {
                    println!("started seat {:?} turn {}", link.seat(), g.turn());
                    game = Some(g);
                }
                GameEvent::Connection(c) => {
                    opponent_here = c == Connection::Connected;
                    println!("connection {c:?}");
                    if let Connection::Closed(_) = c {
                        return ExitCode::FAILURE;
                    }
                }
                GameEvent::Judged { hash, .. } => println!("judged {hash:?}"),
                GameEvent::Refused(why) => println!("refused {why}"),
                _ => {}
            }
        }
        if let (true, false, true, Some(g), Some(seat)) =
            (hosting, broke, opponent_here, &game, link.seat())
        {
            if g.turn() == 0 && g.to_move() == seat {
                if let ClientMessage::Shot { strike, call, .. } = break_shot(g) {
                    link.send(g, seat, Command::Shot { strike, call });
                    println!("shot");
                }
                broke = true;
            }
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    ExitCode::SUCCESS
}
