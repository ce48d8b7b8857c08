//! The window: screens that read input, update and draw, once per frame.

mod capture;
mod clock;
mod draw;
mod input;
mod menu;
mod practice;

use std::path::PathBuf;

use breakshot_shared::scene::Scene;
use macroquad::prelude::{clear_background, next_frame};

use breakshot_client::play::controls::InputFrame;
use breakshot_client::view::palette;

/// Target frame rate: frames are paced by the clock because a virtual display has no vsync.
const FPS: f64 = 60.0;

/// The screen the window opens on.
pub enum Start {
    Menu,
    Practice(Option<Box<Scene>>),
}

/// Options for the whole run.
pub struct Options {
    pub screenshot: Option<PathBuf>,
    pub frames: u32,
}

/// What a screen asks for after a frame.
pub enum Next {
    Stay,
    Quit,
    Go(Screen),
}

pub enum Screen {
    Menu(menu::MenuScreen),
    Practice(Box<practice::PracticeScreen>),
}

impl Screen {
    fn update(&mut self, input: &InputFrame) -> Next {
        match self {
            Screen::Menu(s) => s.update(input),
            Screen::Practice(s) => s.update(input),
        }
    }

    fn draw(&mut self) {
        match self {
            Screen::Menu(s) => s.draw(),
            Screen::Practice(s) => s.draw(),
        }
    }
}

/// Runs the screens until the player quits or the screenshot is taken.
pub async fn run(start: Start, options: Options) -> anyhow::Result<()> {
    let mut screen = match start {
        Start::Menu => Screen::Menu(menu::MenuScreen::new()),
        Start::Practice(scene) => {
            Screen::Practice(Box::new(practice::PracticeScreen::new(scene.map(|s| *s))?))
        }
    };
    let mut clock = clock::FrameClock::new(FPS);
    let mut frames = 0u32;
    loop {
        let dt = clock.frame_time();
        let input = input::read(dt);
        let next = screen.update(&input);
        clear_background(draw::color(palette::BACKGROUND));
        screen.draw();
        frames += 1;
        if let Some(path) = &options.screenshot {
            if frames >= options.frames {
                // Read the frame back now: after next_frame() the buffer is gone.
                return capture::save_screen(path);
            }
        }
        match next {
            Next::Stay => {}
            Next::Quit => return Ok(()),
            Next::Go(s) => screen = s,
        }
        clock.pace();
        next_frame().await;
    }
}
