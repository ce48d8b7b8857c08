//! The native window's command line: parses it, reads what it names and opens the window.

use std::cell::RefCell;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::rc::Rc;

use anyhow::{bail, Context as _};
use breakshot_client::memory::player_name;
use breakshot_client::net::{
    default_data_dir, fetch_game_blocking, HostOptions, NetLink, SeatStore, DEFAULT_PORT,
};
use breakshot_client::play::ReplayViewer;
use breakshot_client::view::ViewKind;
use breakshot_shared::ai::Level;
use breakshot_shared::protocol::{AimAid, Invite, RoomCode, WebLink};
use breakshot_shared::rules::{EightBallRules, Game, Settings, Variant};
use breakshot_shared::scene::Scene;
use clap::{ArgGroup, Args, Parser, Subcommand};

use crate::ui;

#[derive(Parser, Debug)]
#[command(
    name = "breakshot",
    version,
    about = "Breakshot: networked two-player pool"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Render FRAMES frames, save the window as a PNG image to FILE and exit.
    #[arg(long, value_name = "FILE", global = true)]
    screenshot: Option<PathBuf>,
    /// Frames to render before the screenshot is taken.
    #[arg(long, value_name = "N", default_value_t = 5, global = true)]
    frames: u32,
    /// Initial window size, WIDTHxHEIGHT.
    #[arg(long, value_name = "WxH", default_value = "1280x720", global = true)]
    size: String,
    /// Directory for the seats this computer holds in games (to resume them) and, when
    /// hosting, the server's certificate and game store (default: $BREAKSHOT_DATA, else
    /// `breakshot` in the user's data directory, e.g. ~/.local/share/breakshot).
    #[arg(long, value_name = "DIR", global = true)]
    data: Option<PathBuf>,
    /// Open on this view of the table: `top` (flat, from above) or `3d` (default: the view
    /// chosen last with V, else top).
    #[arg(long, value_name = "VIEW", global = true, value_parser = ["top", "3d"])]
    view: Option<String>,
}

/// The games a rules game can be, for `--mode`.
const MODES: [&str; 4] = ["8ball", "9ball", "3cushion", "snooker"];

/// Which game to play: the options of every command that starts a rules game.
#[derive(Args, Debug)]
struct GameArgs {
    /// The game: `8ball`, `9ball`, `3cushion` (three-cushion billiards on the carom
    /// table) or `snooker` (on the 12 ft snooker table).
    #[arg(long, default_value = "8ball", value_parser = MODES)]
    mode: String,
    /// 8-ball's rule set: `wpa` (the World Pool-Billiard Association's rules: ball in hand
    /// after any foul; the 8 on the break is spotted or the balls re-racked) or `bar` (a
    /// scratch while shooting at the 8 loses; the 8 on the break wins). Default `wpa`.
    #[arg(long, value_name = "RULES", value_parser = ["wpa", "bar"])]
    rules: Option<String>,
    /// Three-cushion: the points that win the game, 1 to 1000 (default 15).
    #[arg(long, value_name = "POINTS", value_parser = clap::value_parser!(u32).range(1..=1000))]
    race: Option<u32>,
    /// Snooker: the reds racked each frame, 15, or 10 or 6 for a short game (default 15).
    #[arg(long, value_name = "N", value_parser = ["6", "10", "15"])]
    reds: Option<String>,
    /// Snooker: the frames of the match, an odd number from 1 to 35; the first to win
    /// more than half wins (default 1).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u8).range(1..=35))]
    best_of: Option<u8>,
}

impl GameArgs {
    /// The rules variant these options name; `--rules` and `--race` only where they mean
    /// something.
    fn variant(&self) -> anyhow::Result<Variant> {
        if self.rules.is_some() && self.mode != "8ball" {
            bail!(
                "--rules chooses 8-ball's rule set; it means nothing with --mode {}",
                self.mode
            );
        }
        if self.race.is_some() && self.mode != "3cushion" {
            bail!(
                "--race sets the points of a three-cushion game; it means nothing with --mode {}",
                self.mode
            );
        }
        if (self.reds.is_some() || self.best_of.is_some()) && self.mode != "snooker" {
            bail!(
                "--reds and --best-of set a snooker match; they mean nothing with --mode {}",
                self.mode
            );
        }
        if self.best_of.is_some_and(|n| n % 2 == 0) {
            bail!("--best-of must be odd, so that a match cannot end level");
        }
        Ok(match (self.mode.as_str(), self.rules.as_deref()) {
            ("9ball", _) => Variant::NineBall,
            ("snooker", _) => Variant::Snooker {
                reds: self
                    .reds
                    .as_deref()
                    .and_then(|r| r.parse().ok())
                    .unwrap_or(15),
                best_of: self.best_of.unwrap_or(1),
            },
            ("3cushion", _) => Variant::ThreeCushion {
                race: self.race.unwrap_or(DEFAULT_RACE),
            },
            (_, Some("bar")) => Variant::EightBall(EightBallRules::Bar),
            _ => Variant::EightBall(EightBallRules::Wpa),
        })
    }
}

/// The points a three-cushion game is played to when `--race` does not say.
const DEFAULT_RACE: u32 = 15;

/// The name shown to the other player: the option of the commands that play online.
#[derive(Args, Debug)]
struct NameArg {
    /// Your name as the other player sees it; remembered for next time (default: the name
    /// given last, else your login name).
    #[arg(long, value_name = "NAME")]
    name: Option<String>,
}

/// The seed of the rack: the option of the commands that rack balls at this computer.
#[derive(Args, Debug)]
struct SeedArg {
    /// Seed of the rack (the same seed gives the same rack; default: a new rack each time).
    #[arg(long, value_name = "N")]
    seed: Option<u64>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Host a game and show the invite for the other player.
    Host {
        #[command(flatten)]
        game: GameArgs,
        #[command(flatten)]
        name: NameArg,
        /// UDP address the game server listens on (open this port to the other player).
        #[arg(long, value_name = "ADDR", default_value_t = SocketAddr::from(([0, 0, 0, 0], DEFAULT_PORT)))]
        bind: SocketAddr,
        /// The address the other player dials to reach this computer, written into the
        /// invite (default: this computer's LAN address).
        #[arg(long, value_name = "HOST")]
        address: Option<String>,
        /// Aiming aids allowed in the room: `full`, `first-contact` (aim line and ghost ball),
        /// `off`, or `advice` (full, and the computer's advice, I / J, for every player).
        #[arg(long, value_name = "AIDS", default_value = "full", value_parser = ["full", "first-contact", "off", "advice"])]
        aids: String,
        /// Open a new room even if this computer's last hosted game is unfinished (by
        /// default a restarted host goes back to it: same room, same invite).
        #[arg(long)]
        new: bool,
        /// Play against the computer: it takes the other seat, and a friend who opens the
        /// invite watches (always a new room).
        #[arg(long)]
        computer: bool,
        /// With --computer: how strong it plays, 1 (beginner) to 5 (strong).
        #[arg(long, value_name = "LEVEL", default_value_t = 3, requires = "computer", value_parser = clap::value_parser!(u8).range(1..=5))]
        level: u8,
        /// The address where the web bundle is published (a static HTTPS site): the link
        /// printed opens that page and names this server, reached over WebTransport
        /// (docs/web.md).
        #[arg(long, value_name = "URL", value_parser = WebLink::published_page)]
        web_page: Option<String>,
    },
    /// Join a game with the invite the host sent (a full room is watched).
    Join {
        /// The invite the host's game shows, `breakshot://HOST:PORT/ROOM#FINGERPRINT`
        /// (quote it: it contains `#`).
        #[arg(value_name = "INVITE")]
        invite: String,
        #[command(flatten)]
        name: NameArg,
    },
    /// Two players taking turns at this computer (I: the computer's advice; after a miss,
    /// the shot missed beside the computer's own, the table left to the next player).
    Local {
        #[command(flatten)]
        game: GameArgs,
        #[command(flatten)]
        seed: SeedArg,
    },
    /// Play against the computer at this computer, offline.
    VsComputer {
        /// How strong the computer plays: 1 (beginner) to 5 (strong).
        #[arg(long, value_name = "LEVEL", default_value_t = 3, value_parser = clap::value_parser!(u8).range(1..=5))]
        level: u8,
        #[command(flatten)]
        game: GameArgs,
        /// Who breaks the first game, `me` or `computer` (then the break alternates).
        #[arg(long = "break", value_name = "WHO", default_value = "me", value_parser = ["me", "computer"])]
        breaker: String,
        #[command(flatten)]
        seed: SeedArg,
    },
    /// Play offline with no rules, from a rack or from a scene file.
    Practice {
        /// A scene file (JSON, see docs/scene.md): its table, balls and physics, and its
        /// strike as the first aim; or a position code (`bs1.…`, as O in practice gives).
        #[arg(value_name = "SCENE")]
        scene: Option<PathBuf>,
        /// The table without a scene: an `8ball` or `9ball` rack (`pool` is the 8-ball
        /// rack), the `3cushion` start on the carom table, or the `snooker` rack (15 reds).
        #[arg(long, value_name = "MODE", default_value = "8ball", value_parser = ["8ball", "9ball", "pool", "3cushion", "snooker"], conflicts_with = "scene")]
        mode: String,
        #[command(flatten)]
        seed: SeedArg,
    },
    /// Watch a recorded game: from a file, or from a server by its room code.
    #[command(group(ArgGroup::new("source").required(true).args(["file", "server"])))]
    Replay {
        /// A game record file (saved with `replay --server ... --save FILE`).
        #[arg(value_name = "FILE", conflicts_with = "server")]
        file: Option<PathBuf>,
        /// The server that recorded the game: breakshot://HOST:PORT#FINGERPRINT, as
        /// breakshot-server prints it (a room invite works too).
        #[arg(long, value_name = "URL", requires = "game")]
        server: Option<String>,
        /// The room code of the game (its latest game is shown unless --number says).
        #[arg(long, value_name = "ID", requires = "server")]
        game: Option<String>,
        /// Which of the room's games: 1 for its first, 2 for the one after its first rematch
        /// (default: the latest).
        #[arg(long, value_name = "N", requires = "game", value_parser = clap::value_parser!(u32).range(1..))]
        number: Option<u32>,
        /// Save the fetched game's record to FILE instead of showing it (watch it later
        /// with `breakshot replay FILE`).
        #[arg(long, value_name = "FILE", requires = "server")]
        save: Option<PathBuf>,
    },
}

pub fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Some(dir) = &cli.data {
        ui::use_data_dir(dir.clone());
    }
    // Who the player is on every server: the key pair kept in the data directory.
    match ui::data_dir().map(|d| breakshot_client::memory::identity(&d)) {
        Some(Ok(identity)) => breakshot_client::net::use_identity(identity),
        Some(Err(e)) => eprintln!("breakshot: {e}; playing under a key for this run only"),
        None => {}
    }
    if let Some(Command::Replay {
        server: Some(server),
        game: Some(game),
        number,
        save: Some(path),
        ..
    }) = &cli.command
    {
        return match save_record(server, game, *number, path) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("breakshot: {e:#}");
                ExitCode::from(2)
            }
        };
    }
    match prepare(&cli) {
        Ok(start) => open_window(&cli, start),
        Err(e) => {
            eprintln!("breakshot: {e:#}");
            ExitCode::from(2)
        }
    }
}

/// Everything that can fail before a window opens: reading files, checking arguments.
fn prepare(cli: &Cli) -> anyhow::Result<ui::Start> {
    if cli.frames == 0 {
        bail!("--frames must be at least 1");
    }
    parse_size(&cli.size)?;
    Ok(match &cli.command {
        None => ui::Start::Menu,
        Some(Command::Practice {
            scene: None,
            mode,
            seed,
        }) => match mode.as_str() {
            "9ball" => ui::Start::Practice(Some(Box::new(opening_scene(
                Variant::NineBall,
                seed.seed.unwrap_or_else(ui::fresh_seed),
            )))),
            "3cushion" => {
                ui::Start::Practice(Some(Box::new(opening_scene(Variant::three_cushion(), 0))))
            }
            "snooker" => ui::Start::Practice(Some(Box::new(opening_scene(
                Variant::snooker(),
                seed.seed.unwrap_or_else(ui::fresh_seed),
            )))),
            _ => ui::Start::Practice(None),
        },
        Some(Command::Practice {
            scene: Some(path), ..
        }) => {
            // A position code stands where a scene file's path does.
            let given = path.to_string_lossy();
            let text = if given.starts_with(breakshot_shared::scene_code::PREFIX) {
                given.into_owned()
            } else {
                std::fs::read_to_string(path)
                    .with_context(|| format!("cannot read {}", path.display()))?
            };
            // A drill file is a scene with a goal: its table, played as the drill.
            let drill = serde_json::from_str::<serde_json::Value>(&text)
                .ok()
                .filter(|v| v.get("goal").is_some());
            if drill.is_some() {
                let drill = breakshot_client::play::drill::Drill::from_json(&text)
                    .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
                ui::Start::Drill(Box::new(drill))
            } else {
                let scene = breakshot_client::play::position::read(&text)
                    .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
                ui::Start::Practice(Some(Box::new(scene)))
            }
        }
        Some(Command::Local { game, .. }) => ui::Start::Local(game.variant()?),
        Some(Command::VsComputer {
            level,
            game,
            breaker,
            ..
        }) => ui::Start::VsComputer {
            variant: game.variant()?,
            level: Level::new(*level),
            computer_breaks: breaker == "computer",
        },
        Some(Command::Host {
            game,
            name: name_arg,
            bind,
            address,
            aids,
            new,
            computer,
            level,
            web_page,
        }) => {
            let options = HostOptions {
                bind: *bind,
                variant: game.variant()?,
                aim_aid: aim_aid(aids),
                address: address.clone(),
                resume: !new,
                name: name(cli, name_arg)?,
                computer: computer.then(|| Level::new(*level)),
                web_page: web_page.clone(),
                ..HostOptions::new(data_dir(cli)?)
            };
            host(&options)?
        }
        Some(Command::Join {
            invite,
            name: name_arg,
        }) => {
            let invite: Invite = invite
                .parse()
                .with_context(|| format!("{invite:?} is not an invite"))?;
            let seats = SeatStore::new(&data_dir(cli)?);
            let link = NetLink::join(invite, &name(cli, name_arg)?, Some(seats))?;
            ui::Start::Network(Box::new(link))
        }
        Some(Command::Replay {
            file: Some(file), ..
        }) => {
            let bytes =
                std::fs::read(file).with_context(|| format!("cannot read {}", file.display()))?;
            let viewer = ReplayViewer::decode(&bytes)
                .with_context(|| format!("{} is not a game record", file.display()))?;
            ui::Start::Replay(Box::new(viewer))
        }
        Some(Command::Replay {
            server: Some(server),
            game: Some(game),
            number,
            ..
        }) => ui::Start::Replay(Box::new(fetch_replay(server, game, *number)?)),
        Some(Command::Replay { .. }) => bail!("give a record FILE, or --server URL --game ID"),
    })
}

/// The player's name: `--name` (remembered), else the one remembered in the data directory.
fn name(cli: &Cli, arg: &NameArg) -> anyhow::Result<String> {
    player_name(&data_dir(cli)?, arg.name.as_deref()).map_err(anyhow::Error::msg)
}

/// The rack's seed the command gives, if it racks balls at this computer.
fn seed(cli: &Cli) -> Option<u64> {
    match &cli.command {
        Some(Command::Local { seed, .. })
        | Some(Command::VsComputer { seed, .. })
        | Some(Command::Practice { seed, .. }) => seed.seed,
        _ => None,
    }
}

/// The data directory: `--data`, else the default (see [`default_data_dir`]).
fn data_dir(cli: &Cli) -> anyhow::Result<PathBuf> {
    match &cli.data {
        Some(d) => Ok(d.clone()),
        None => {
            default_data_dir().context("no user data directory (HOME is not set): give --data DIR")
        }
    }
}

/// Fetches a game's record from the server `url` names and opens it.
fn fetch_replay(url: &str, game: &str, number: Option<u32>) -> anyhow::Result<ReplayViewer> {
    let (room, bytes) = fetch(url, game, number)?;
    ReplayViewer::decode(&bytes)
        .with_context(|| format!("the server sent game {room} as an unreadable record"))
}

/// Fetches a game's record from a server and saves it to `path`, checked as a record first.
fn save_record(
    url: &str,
    game: &str,
    number: Option<u32>,
    path: &std::path::Path,
) -> anyhow::Result<()> {
    let (room, bytes) = fetch(url, game, number)?;
    ReplayViewer::decode(&bytes)
        .with_context(|| format!("the server sent game {room} as an unreadable record"))?;
    std::fs::write(path, &bytes).with_context(|| format!("cannot write {}", path.display()))?;
    eprintln!(
        "breakshot: saved to {} (watch it with: breakshot replay {})",
        path.display(),
        path.display()
    );
    Ok(())
}

/// The record of room `game`'s game `number` (the latest if `None`) on the server at `url`.
fn fetch(url: &str, game: &str, number: Option<u32>) -> anyhow::Result<(RoomCode, Vec<u8>)> {
    let server: Invite = url.parse().with_context(|| {
        format!("{url:?} is not a server address (breakshot://HOST:PORT#FINGERPRINT)")
    })?;
    let room = RoomCode::parse(game).with_context(|| format!("{game:?} is not a room code"))?;
    let fetched = fetch_game_blocking(&server, &room, number)
        .with_context(|| format!("cannot fetch game {room} from {}", server.authority()))?;
    eprintln!(
        "breakshot: game {} of room {room} ({})",
        fetched.game,
        if fetched.finished {
            "finished"
        } else {
            "still being played"
        }
    );
    Ok((room, fetched.bytes))
}

/// Hosts a game, tells the terminal where it is served, and plays in it.
#[cfg(feature = "host")]
fn host(options: &HostOptions) -> anyhow::Result<ui::Start> {
    let host = breakshot_client::net::Host::start(options)?;
    announce(&host);
    Ok(ui::Start::Network(Box::new(host)))
}

/// This build has no embedded server.
#[cfg(not(feature = "host"))]
fn host(_: &HostOptions) -> anyhow::Result<ui::Start> {
    Err(breakshot_client::net::HostError::NotBuilt.into())
}

/// Tells the terminal where the game is served and what to send the other player.
#[cfg(feature = "host")]
fn announce(host: &breakshot_client::net::Host) {
    if host.resumed() {
        let room = host.invite().room.as_ref().map(|r| r.to_string());
        eprintln!(
            "breakshot: back to your unfinished game in room {} (start with --new for a new room)",
            room.unwrap_or_default()
        );
    }
    println!("{}", host.invite());
    if let Some(link) = host.web_link() {
        println!("{link}");
    }
    let whom = match host.computer() {
        Some(level) => format!(
            "the computer (level {}) plays the other seat; send the invite above to a friend \
             to watch",
            level.number()
        ),
        None if host.web_link().is_some() => {
            "send the other player the invite above, or the link to play in a browser".into()
        }
        None => "send the invite above to the other player".into(),
    };
    eprintln!(
        "breakshot: serving on UDP {} (data in {}); {whom}",
        host.server().local_addr(),
        host.data().display()
    );
    if host.needs_address() {
        eprintln!("breakshot: {}", breakshot_client::net::ADDRESS_NOTE);
    } else {
        let port = host.server().local_addr().port();
        eprintln!(
            "breakshot: {}",
            breakshot_client::net::router_hint(port, host.web_link().is_some())
        );
    }
}

/// The aim-aid policy named by `--aids` (checked by the parser).
fn aim_aid(name: &str) -> AimAid {
    match name {
        "off" => AimAid::Off,
        "first-contact" => AimAid::FirstContact,
        "advice" => AimAid::Advice,
        _ => AimAid::Full,
    }
}

fn parse_size(text: &str) -> anyhow::Result<(i32, i32)> {
    let parsed = text.split_once(['x', 'X']).and_then(|(w, h)| {
        let (w, h) = (w.trim().parse::<i32>().ok()?, h.trim().parse::<i32>().ok()?);
        ((320..=8192).contains(&w) && (240..=8192).contains(&h)).then_some((w, h))
    });
    parsed.with_context(|| {
        format!("--size must be WIDTHxHEIGHT (320x240 to 8192x8192), not {text:?}")
    })
}

fn open_window(cli: &Cli, start: ui::Start) -> ExitCode {
    let (width, height) = parse_size(&cli.size).unwrap_or((1280, 720));
    let conf = macroquad::miniquad::conf::Conf {
        window_title: "Breakshot".to_string(),
        window_width: width,
        window_height: height,
        window_resizable: true,
        high_dpi: false,
        ..Default::default()
    };
    let options = ui::Options {
        screenshot: cli.screenshot.clone(),
        frames: cli.frames,
        seed: seed(cli),
        view: cli.view.as_deref().and_then(ViewKind::parse),
        data: data_dir(cli).ok(),
    };
    let result: Rc<RefCell<Option<anyhow::Result<()>>>> = Rc::new(RefCell::new(None));
    let slot = result.clone();
    macroquad::Window::from_config(conf, async move {
        let outcome = ui::run(start, options).await;
        *slot.borrow_mut() = Some(outcome);
    });
    let outcome = result.borrow_mut().take();
    match outcome {
        Some(Err(e)) => {
            eprintln!("breakshot: {e:#}");
            ExitCode::FAILURE
        }
        _ => ExitCode::SUCCESS,
    }
}

/// `variant`'s opening position (shuffled by `seed`) as a scene, for the practice table.
fn opening_scene(variant: Variant, seed: u64) -> Scene {
    Game::new(variant, Settings::offline(), seed).scene()
}
