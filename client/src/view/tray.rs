//! Whose tray a pocketed ball goes in. In 8-ball, once the groups are decided, each player's
//! tray holds the balls of their group that are down; the 8 (and anything down while the
//! table is open) lies between them. 9-ball has no groups: one tray.

use breakshot_shared::rules::{Game, Seat, Variant};

/// The pocketed balls sorted into trays.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Trays {
    /// The balls of each seat's group (A, B), in the order given.
    pub seats: [Vec<usize>; 2],
    /// The rest: the 8, and balls whose group is not decided.
    pub between: Vec<usize>,
}

/// `pocketed` (ball numbers) sorted by whose group they belong to in `game`; None when the
/// game has no groups (9-ball).
pub fn trays(game: &Game, pocketed: &[usize]) -> Option<Trays> {
    if game.variant() == Variant::NineBall {
        return None;
    }
    let mut t = Trays::default();
    for &b in pocketed {
        let owner = [Seat::A, Seat::B].into_iter().position(|seat| {
            game.group_of(seat)
                .is_some_and(|g| u8::try_from(b).is_ok_and(|n| g.balls().contains(&n)))
        });
        match owner {
            Some(k) => t.seats[k].push(b),
            None => t.between.push(b),
        }
    }
    Some(t)
}

/// The name each seat's tray is labelled with: the player's name when known, else the seat.
pub fn seat_names(names: &[Option<String>; 2]) -> [String; 2] {
    [Seat::A, Seat::B].map(|s| {
        names[usize::from(s == Seat::B)]
            .clone()
            .unwrap_or_else(|| s.to_string())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_games::eight_ball;
    use breakshot_shared::rules::Settings;

    #[test]
    fn an_open_table_puts_every_ball_between_and_nine_ball_has_no_trays() {
        let game = eight_ball(1);
        let t = trays(&game, &[3, 12, 8]).expect("8-ball has trays");
        assert_eq!(t.between, vec![3, 12, 8]);
        assert!(t.seats.iter().all(Vec::is_empty));
        let nine = Game::new(Variant::NineBall, Settings::offline(), 1);
        assert_eq!(trays(&nine, &[3]), None);
    }

    #[test]
    fn once_the_groups_are_decided_each_player_s_tray_holds_their_group() {
        use breakshot_shared::ai::{self, Level};
        use breakshot_shared::rules::is_off_table;
        // A strong computer plays both seats until someone has pocketed a ball of a group.
        let mut game = eight_ball(3);
        for turn in 0..60 {
            if game.group_of(Seat::A).is_some() {
                break;
            }
            let command = ai::decide(&game, Level::new(5), turn).expect("a move");
            let seat = game.to_move();
            game.apply(seat, &command)
                .expect("the computer's move is legal");
        }
        let groups = [Seat::A, Seat::B].map(|s| game.group_of(s).expect("groups decided"));
        let balls = game.balls();
        let pocketed: Vec<usize> = (1..balls.len())
            .filter(|&b| is_off_table(&balls[b]))
            .collect();
        assert!(!pocketed.is_empty());
        let t = trays(&game, &pocketed).expect("8-ball has trays");
        for (k, group) in groups.iter().enumerate() {
            assert!(t.seats[k]
                .iter()
                .all(|&b| group.balls().contains(&(b as u8))));
        }
        // Every ball is in one tray, the 8 between.
        let mut all: Vec<usize> = t.seats.concat();
        all.extend(&t.between);
        all.sort_unstable();
        assert_eq!(all, pocketed);
        assert!(t.between.iter().all(|&b| b == 8));
        assert!(t.seats.iter().any(|s| !s.is_empty()));
    }

    /// The shot that decides the groups: while it plays, the balls it pockets lie between
    /// the trays (the table was open when it was struck); once it is over they go to the
    /// groups it decided. The screens sort the trays by `GameFlow::shown_game` for this.
    #[test]
    fn a_ball_pocketed_on_an_open_table_joins_a_tray_only_once_the_groups_are_decided() {
        use crate::play::{GameEvent, GameFlow};
        use crate::view::hud::Connection;
        use breakshot_shared::ai::{self, Level};
        use breakshot_shared::rules::{Command, TurnId};
        // A strong computer plays both seats; the game just before the shot that decides
        // the groups, and that shot.
        let mut game = eight_ball(3);
        let (before, seat, command) = (0..60)
            .find_map(|turn| {
                let command = ai::decide(&game, Level::new(5), turn).expect("a move");
                let seat = game.to_move();
                let before = game.clone();
                game.apply(seat, &command)
                    .expect("the computer's move is legal");
                let decides = before.group_of(seat).is_none() && game.group_of(seat).is_some();
                decides.then_some((before, seat, command))
            })
            .expect("the groups are decided within 60 turns");
        assert!(matches!(command, Command::Shot { .. }));
        let turn: TurnId = before.turn();

        let mut flow = GameFlow::new(Connection::Offline);
        flow.handle(GameEvent::Started(Box::new(before.clone())));
        let down_before = flow.tray();
        flow.handle(GameEvent::Decided {
            turn,
            seat,
            command,
        });
        // The shot plays: tick until one of its balls has fallen while it is still shown.
        let mut seen_between = false;
        for _ in 0..60 * 60 {
            if flow.shot().is_none() {
                break;
            }
            let pocketed = flow.tray();
            let new: Vec<usize> = pocketed
                .iter()
                .copied()
                .filter(|b| *b != 0 && !down_before.contains(b))
                .collect();
            if !new.is_empty() {
                let shown = flow.shown_game().expect("a game");
                let t = trays(shown, &pocketed).expect("8-ball has trays");
                for b in &new {
                    assert!(
                        t.between.contains(b),
                        "ball {b} is in a player's tray before the shot is over: {t:?}"
                    );
                }
                seen_between = true;
            }
            flow.tick(1.0 / 60.0);
        }
        assert!(seen_between, "no ball fell while the shot was shown");
        assert!(
            flow.shot().is_none(),
            "the shot did not end within a minute"
        );
        // Over: the shooter's group holds its balls, in the shooter's tray.
        let shown = flow.shown_game().expect("a game");
        let group = shown.group_of(seat).expect("groups decided");
        let pocketed = flow.tray();
        let t = trays(shown, &pocketed).expect("8-ball has trays");
        let mine = &t.seats[usize::from(seat == Seat::B)];
        assert!(!mine.is_empty(), "the shooter's tray is empty: {t:?}");
        assert!(mine.iter().all(|&b| group.balls().contains(&(b as u8))));
    }

    #[test]
    fn a_tray_is_labelled_with_the_player_s_name_or_the_seat() {
        let names = [None, Some("ann".to_string())];
        assert_eq!(
            seat_names(&names),
            ["Player A".to_string(), "ann".to_string()]
        );
    }
}
