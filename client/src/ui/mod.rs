//! The window: screens that read input, update and draw, once per frame.

mod capture;
pub mod clock;
mod draw;
mod game;
mod hud;
mod input;
mod invite;
mod lobby;
mod menu;
#[cfg(target_arch = "wasm32")]
pub mod page_game;
mod panel;
pub(crate) mod practice;
mod replay;
mod snooker;
mod speaker;
mod table3d;
mod table_view;
mod trays;

use std::path::PathBuf;

use breakshot_shared::scene::Scene;
use macroquad::prelude::{clear_background, next_frame};

use breakshot_client::memory;
use breakshot_client::play::{
    open_dropped, ComputerLink, Dropped, GameLink, InputFrame, LocalLink, ReplayViewer,
};
use breakshot_client::view::hud::Connection;
use breakshot_client::view::{palette, Playback, ViewKind};
use breakshot_shared::ai::Level;
use breakshot_shared::rules::{Seat, Settings, Variant};

/// How long a screenshot waits for a network game's first answer from the server.
const SCREENSHOT_PATIENCE: std::time::Duration = std::time::Duration::from_secs(20);

/// Target frame rate: frames are paced by the clock because a virtual display has no vsync.
const FPS: f64 = 60.0;

/// The screen the window opens on.
pub enum Start {
    Menu,
    Practice(Option<Box<Scene>>),
    /// A drill: its position, each shot an attempt scored against its goal.
    Drill(Box<breakshot_client::play::drill::Drill>),
    Replay(Box<ReplayViewer>),
    /// Two players at this computer.
    Local(Variant),
    /// One player against the computer.
    VsComputer {
        variant: Variant,
        level: Level,
        computer_breaks: bool,
    },
    /// A game over the network (hosted here, or joined).
    Network(Box<dyn GameLink>),
    /// A server's lobby: public games to join or watch, and quick match.
    Lobby,
}

/// Options for the whole run.
pub struct Options {
    pub screenshot: Option<PathBuf>,
    pub frames: u32,
    /// Seed of the practice rack (random if not given).
    pub seed: Option<u64>,
    /// The view to open on (else the one remembered in `data`).
    pub view: Option<ViewKind>,
    /// The data directory, where the view chosen is remembered.
    pub data: Option<PathBuf>,
}

/// The data directory `--data` named, for the menu's host, join and resume.
static DATA_DIR: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();

/// Makes the menu use `dir` as its data directory (what `--data` gives).
#[cfg(not(target_arch = "wasm32"))]
pub fn use_data_dir(dir: std::path::PathBuf) {
    let _ = DATA_DIR.set(dir);
}

/// The data directory for the menu: `--data`, else the default one.
pub fn data_dir() -> Option<std::path::PathBuf> {
    let dir = DATA_DIR.get().cloned();
    // A page has no files: nothing is remembered between visits.
    #[cfg(not(target_arch = "wasm32"))]
    let dir = dir.or_else(breakshot_client::net::default_data_dir);
    dir
}

pub use clock::fresh_seed;

/// Tells whoever watches (the page's status line, a test) that `line` happened: the page
/// hears it; the native window writes it to standard error when `BREAKSHOT_REPORT` is set.
pub fn report(line: &str) {
    #[cfg(target_arch = "wasm32")]
    breakshot_client::net::page::report(line);
    #[cfg(not(target_arch = "wasm32"))]
    if reporting() {
        eprintln!("report: {line}");
    }
}

/// Whether anyone hears [`report`]: the page always; a native window only with
/// `BREAKSHOT_REPORT` set (read once), so a screen need not word its lines for nobody.
pub fn reporting() -> bool {
    #[cfg(target_arch = "wasm32")]
    return true;
    #[cfg(not(target_arch = "wasm32"))]
    {
        static ON: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
        *ON.get_or_init(|| std::env::var_os("BREAKSHOT_REPORT").is_some())
    }
}

/// What a screen asks for after a frame.
pub enum Step {
    Stay,
    Quit,
    /// Another screen: screens never make each other, they name the one to open.
    Open(Start),
}

/// The seats of a game against the computer by name: the computer with its level, the
/// player as online games name them (the name remembered, else the login name).
fn computer_game_names(computer: Seat, level: Level) -> [Option<String>; 2] {
    let player = data_dir()
        .and_then(|d| memory::player_name(&d, None).ok())
        .unwrap_or_else(|| "You".to_owned());
    let computer_name = format!("Computer (level {})", level.number());
    match computer {
        Seat::A => [Some(computer_name), Some(player)],
        Seat::B => [Some(player), Some(computer_name)],
    }
}

/// The screen `start` names; `seed` shuffles a new rack (from the clock if not given).
fn open(start: Start, seed: Option<u64>) -> anyhow::Result<Screen> {
    let seed = seed.unwrap_or_else(fresh_seed);
    let game = |link: Box<dyn GameLink>, connection| {
        Screen::Game(Box::new(game::GameScreen::new(link, connection)))
    };
    let screen = match start {
        Start::Menu => Screen::Menu(menu::MenuScreen::new()),
        Start::Lobby => Screen::Lobby(Box::new(lobby::LobbyScreen::new())),
        Start::Network(link) => game(link, Connection::Connecting),
        Start::Local(variant) => game(
            Box::new(LocalLink::new(variant, Settings::offline(), seed)),
            Connection::Offline,
        ),
        Start::VsComputer {
            variant,
            level,
            computer_breaks,
        } => {
            let link =
                ComputerLink::new(variant, Settings::offline(), seed, level, computer_breaks);
            let names = computer_game_names(link.computer().seat(), level);
            Screen::Game(Box::new(
                game::GameScreen::new(Box::new(link), Connection::Offline).with_names(names),
            ))
        }
        Start::Replay(viewer) => Screen::Replay(Box::new(replay::ReplayScreen::new(*viewer))),
        Start::Practice(scene) => Screen::Practice(Box::new(practice::PracticeScreen::new(
            scene.map(|s| *s),
            seed,
        )?)),
        Start::Drill(drill) => Screen::Practice(Box::new(practice::PracticeScreen::drill(*drill)?)),
    };
    report(match screen {
        Screen::Menu(_) => "screen menu",
        Screen::Lobby(_) => "screen lobby",
        Screen::Practice(_) => "screen practice",
        Screen::Replay(_) => "screen replay",
        Screen::Game(_) => "screen game",
    });
    Ok(screen)
}

pub enum Screen {
    Menu(menu::MenuScreen),
    Lobby(Box<lobby::LobbyScreen>),
    Practice(Box<practice::PracticeScreen>),
    Replay(Box<replay::ReplayScreen>),
    Game(Box<game::GameScreen>),
}

impl Screen {
    fn update(&mut self, input: &InputFrame) -> Step {
        match self {
            Screen::Menu(s) => s.update(input),
            Screen::Lobby(s) => s.update(input),
            Screen::Practice(s) => s.update(input),
            Screen::Replay(s) => s.update(input),
            Screen::Game(s) => s.update(input),
        }
    }

    /// The shot being shown, if any.
    fn shot(&self) -> Option<&Playback> {
        match self {
            Screen::Menu(_) => None,
            Screen::Lobby(_) => None,
            Screen::Practice(s) => s.shot(),
            Screen::Replay(s) => s.shot(),
            Screen::Game(s) => s.shot(),
        }
    }

    /// True while the screen waits for the server's first answer.
    /// True while a line of text is being typed (the chat): it takes the keys.
    fn typing(&self) -> bool {
        matches!(self, Screen::Game(s) if s.typing())
            || matches!(self, Screen::Menu(s) if s.typing())
    }

    fn awaiting_server(&self) -> bool {
        matches!(self, Screen::Game(s) if s.awaiting_server())
    }

    fn draw(&mut self) {
        match self {
            Screen::Menu(s) => s.draw(),
            Screen::Lobby(s) => s.draw(),
            Screen::Practice(s) => s.draw(),
            Screen::Replay(s) => s.draw(),
            Screen::Game(s) => s.draw(),
        }
    }
}

/// The frame times of a run, each frame's work (ms) and whether balls were moving in it:
/// how many frames, their median and 90th percentile, of all and of those with balls moving.
fn frame_times(work: &[(f64, bool)]) -> Option<String> {
    let stats = |mut ms: Vec<f64>| {
        ms.sort_by(f64::total_cmp);
        let at = |q: f64| ms[((ms.len() - 1) as f64 * q).round() as usize];
        (!ms.is_empty()).then(|| {
            format!(
                "{} frames: {:.1} ms (median), {:.1} ms (90th percentile)",
                ms.len(),
                at(0.5),
                at(0.9)
            )
        })
    };
    let all = stats(work.iter().map(|w| w.0).collect())?;
    let moving = stats(work.iter().filter(|w| w.1).map(|w| w.0).collect());
    Some(match moving {
        Some(m) => format!("work per frame, {all}; with balls moving, {m}"),
        None => format!("work per frame, {all}"),
    })
}

/// Runs the screens until the player quits or the screenshot is taken.
pub async fn run(start: Start, options: Options) -> anyhow::Result<()> {
    let remembered = options.data.as_deref().and_then(memory::remembered_view);
    table_view::start(
        options.view.or(remembered).unwrap_or_default(),
        options.data.clone(),
    );
    let seed = options.seed;
    let mut screen = open(start, seed)?;
    let mut clock = clock::FrameClock::new(FPS);
    let mut frames = 0u32;
    let started = clock::now();
    let mut speaker = speaker::Speaker::new().await;
    // Each frame's work (not its pacing), for the figure a screenshot run prints.
    let mut work = Vec::new();
    let mut moving = false;
    input::catch_quit();
    loop {
        if input::quit_requested() {
            // Returning drops the screen: its connection closes and a hosted server stops.
            return Ok(());
        }
        let real_dt = clock.frame_time();
        if frames > 0 {
            work.push((clock.work_ms(), moving));
        }
        // A screenshot shows frame N of the animation at FPS, whatever the machine's speed:
        // on a loaded or software-rendered display frames take longer than 1/FPS.
        let dt = if options.screenshot.is_some() {
            1.0 / FPS
        } else {
            real_dt
        };
        let input = input::read(dt, screen.typing());
        let mut next = screen.update(&input);
        // A file dropped on the window opens: a record to watch, a scene to practise on.
        if let Some(bytes) = input.dropped.last() {
            next = match open_dropped(bytes) {
                Ok(Dropped::Record(viewer)) => Step::Open(Start::Replay(viewer)),
                Ok(Dropped::Scene(scene)) => Step::Open(Start::Practice(Some(scene))),
                Err(why) => {
                    report(&format!("status {why}"));
                    screen = Screen::Menu(menu::MenuScreen::with_message(why));
                    Step::Stay
                }
            };
        }
        speaker.keys(&input);
        speaker.hear(screen.shot());
        clear_background(draw::color(palette::BACKGROUND));
        screen.draw();
        moving = screen.shot().is_some();
        frames += 1;
        if let Some(path) = &options.screenshot {
            // A screenshot of a network game shows the server's first answer, if it comes
            // within SCREENSHOT_PATIENCE.
            let answered = !screen.awaiting_server()
                || clock::now().saturating_sub(started) > SCREENSHOT_PATIENCE;
            if frames >= options.frames && answered {
                // Read the frame back now: after next_frame() the buffer is gone.
                capture::save_screen(path)?;
                if let Some(line) = frame_times(&work) {
                    eprintln!("breakshot: {line}");
                }
                return Ok(());
            }
        }
        match next {
            Step::Stay => {}
            Step::Quit => return Ok(()),
            Step::Open(start) => {
                screen = open(start, None)
                    .unwrap_or_else(|e| Screen::Menu(menu::MenuScreen::with_message(e.to_string())))
            }
        }
        clock.pace();
        next_frame().await;
    }
}
