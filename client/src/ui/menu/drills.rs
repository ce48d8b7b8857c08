//! The menu's page of drills: the drills that ship with the game, each with the score this
//! computer remembers for it; a click plays one, Esc or *Back* returns to the menu.

use breakshot_client::memory::drill_score;
use breakshot_client::play::drill::{Drill, Score};
use breakshot_client::play::{InputFrame, Key};
use breakshot_client::view::{menu_buttons, Rect};
use macroquad::prelude::*;

use super::super::draw::{self, Align};

/// What the page asks of the menu after a frame.
pub enum PageStep {
    Stay,
    /// Back to the menu's buttons.
    Back,
    /// Play this drill.
    Play(Box<Drill>),
}

pub struct DrillsPage {
    /// The shipped drills and their remembered scores (none in a browser, which keeps no
    /// files).
    drills: Vec<(Drill, Option<Score>)>,
    mouse: [f32; 2],
}

impl DrillsPage {
    pub fn open() -> DrillsPage {
        let data = crate::ui::data_dir();
        let drills = Drill::shipped()
            .into_iter()
            .map(|d| {
                let score = data.as_ref().map(|dir| drill_score(dir, &d.name));
                (d, score)
            })
            .collect();
        DrillsPage {
            drills,
            mouse: [-1.0, -1.0],
        }
    }

    /// The drills' buttons and, last, *Back*.
    fn buttons(&self) -> Vec<Rect> {
        menu_buttons(screen_width(), screen_height(), self.drills.len() + 1)
    }

    pub fn update(&mut self, input: &InputFrame) -> PageStep {
        self.mouse = input.mouse;
        if input.pressed.contains(&Key::Back) {
            return PageStep::Back;
        }
        if !input.left_pressed {
            return PageStep::Stay;
        }
        let hit = self.buttons().iter().position(|r| r.contains(input.mouse));
        match hit {
            Some(k) if k < self.drills.len() => PageStep::Play(Box::new(self.drills[k].0.clone())),
            Some(_) => PageStep::Back,
            None => PageStep::Stay,
        }
    }

    pub fn draw(&self) {
        let (w, h) = (screen_width(), screen_height());
        let title = "Drills";
        let size = 56.0f32.min(0.1 * h);
        let tw = draw::text_width(title, size);
        draw::label(title, 0.5 * (w - tw), 0.18 * h, size, WHITE);
        let labels = self
            .drills
            .iter()
            .map(|(d, score)| match score {
                Some(s) if s.attempts > 0 => format!("{}  -  {}", d.name, s.line()),
                _ => d.name.clone(),
            })
            .chain(std::iter::once("Back".to_owned()));
        let buttons: Vec<(Rect, String)> = self.buttons().into_iter().zip(labels).collect();
        let inside = |r: &Rect| Rect::new(r.x + 8.0, r.y + 2.0, r.w - 16.0, r.h - 4.0);
        // One size for every label: the largest at which the longest fits its button.
        let size = buttons
            .iter()
            .map(|(r, label)| {
                let b = inside(r);
                draw::fitted_size(label, b.w, b.h, 24.0)
            })
            .fold(24.0, f32::min);
        for (r, label) in buttons {
            draw::button_face(r, r.contains(self.mouse));
            draw::label_in(&label, inside(&r), size, Align::Centre, WHITE);
        }
    }
}
