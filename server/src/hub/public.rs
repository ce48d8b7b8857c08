//! What the hub does for players who come without an invite: listing a public room, the
//! quick-match queue and the rooms it opens, rating a quick match's game when it ends, and
//! telling everyone of a drain. The state itself is pure and kept elsewhere
//! ([`crate::lobby`], [`crate::matchmaking`], [`crate::ratings`]); this is the glue that
//! turns it into the hub's outputs.

use std::time::Instant;

use breakshot_shared::protocol::limits::QUEUE_TIMEOUT;
use breakshot_shared::protocol::{AimAid, ErrorCode, Role, RoomCode, ServerMessage};
use breakshot_shared::rules::{Phase, Seat, Settings, Variant};

use super::{error, lift, send, Greeting, Hub, Output, RatedGame};
use crate::lobby::{Listed, Listing};
use crate::matchmaking::{Match, Waiting};
use crate::output::{ConnId, RoomOutput, StoreOp};
use crate::room::{Room, RoomRules};
use crate::secret::{new_seed, new_token, TokenDigest};

impl Hub {
    /// Opens no new room from now on (the games in play go on): the server drains. The first
    /// call tells every player so and empties the quick-match queues; later calls do nothing.
    pub fn drain(&mut self) -> Vec<Output> {
        if self.draining {
            return Vec::new();
        }
        self.draining = true;
        let mut out = Vec::new();
        let queued: Vec<ConnId> = self
            .conns
            .keys()
            .copied()
            .filter(|c| self.queues.is_queued(*c))
            .collect();
        for conn in queued {
            self.queues.leave(conn);
            out.push(send(
                conn,
                ServerMessage::Unqueued {
                    reason: "this server is shutting down; find a game on another".into(),
                },
            ));
        }
        for (&conn, c) in &self.conns {
            if matches!(c.greeting, Greeting::Welcomed(_)) {
                let message = if c.room.is_some() {
                    "this server is shutting down: your game goes on to its end, but no new game can start here"
                } else {
                    "this server is shutting down and starts no new games; find a game on another"
                };
                out.push(send(
                    conn,
                    ServerMessage::Draining {
                        message: message.into(),
                    },
                ));
            }
        }
        out
    }

    /// Lists the room `conn` created, while it waits for its second player.
    pub(super) fn publish(
        &mut self,
        now: Instant,
        conn: ConnId,
        in_room: Option<(RoomCode, Role)>,
    ) -> Vec<Output> {
        let Some((code, Role::Player(Seat::A))) = in_room else {
            return error(
                conn,
                ErrorCode::Unexpected,
                "only the player who created a room can list it",
            );
        };
        let Some(room) = self.rooms.get(&code) else {
            return error(conn, ErrorCode::ServerBusy, "the room is busy; try again");
        };
        if !room.is_waiting() {
            return error(
                conn,
                ErrorCode::Unexpected,
                "the room has both its players: nothing to list",
            );
        }
        if !self.lobby.is_listed(&code) {
            let snapshot = room.snapshot(now);
            let host = snapshot.seats[0]
                .as_ref()
                .map_or_else(String::new, |s| s.name.clone());
            let listing = Listing {
                variant: room.game().variant(),
                mode: room.game().settings(),
                host: Listed {
                    name: host,
                    key: self.player_of(conn),
                },
                guest: None,
                since: now,
                rated: false,
            };
            let players = [listing.host.key, None];
            self.lobby.list(code.clone(), listing);
            return vec![
                Output::Room(RoomOutput::Store(StoreOp::Listed {
                    room: code.clone(),
                    players,
                })),
                send(conn, ServerMessage::Published { room: code }),
            ];
        }
        vec![send(conn, ServerMessage::Published { room: code })]
    }

    /// Queues `conn` for a quick match, and pairs whoever can be paired now.
    pub(super) fn queue(
        &mut self,
        now: Instant,
        conn: ConnId,
        variant: Variant,
        mode: Settings,
        name: String,
    ) -> Vec<Output> {
        if let Some(refused) = self.refuse_while_draining(conn) {
            return refused;
        }
        let (Some(key), Some(source)) =
            (self.player_of(conn), self.conns.get(&conn).map(|c| c.addr))
        else {
            return Vec::new();
        };
        let who = Waiting {
            conn,
            key,
            source,
            name,
            rating: self.ratings.or_start(&key),
            since: now,
        };
        let waiting = match self.queues.join(variant, mode, who) {
            Ok(n) => n,
            Err(_) => {
                return error(
                    conn,
                    ErrorCode::Unexpected,
                    "this player already waits for a quick match",
                )
            }
        };
        let mut out = vec![send(
            conn,
            ServerMessage::Queued {
                waiting: u32::try_from(waiting).unwrap_or(u32::MAX),
                timeout_s: QUEUE_TIMEOUT.as_secs() as u32,
            },
        )];
        out.extend(self.match_queued(now));
        out
    }

    /// Times out players who waited too long and opens a room for every pair found.
    pub(super) fn match_queued(&mut self, now: Instant) -> Vec<Output> {
        let mut out = Vec::new();
        for gone in self.queues.expire(now) {
            out.push(send(
                gone.conn,
                ServerMessage::Unqueued {
                    reason: "no opponent was found in time; try again".into(),
                },
            ));
        }
        for found in self.queues.pairs(now) {
            if self.full() {
                for conn in [found.a.conn, found.b.conn] {
                    out.push(send(
                        conn,
                        ServerMessage::Unqueued {
                            reason: "the server is full; try later".into(),
                        },
                    ));
                }
                continue;
            }
            out.extend(self.open_match(now, found));
        }
        out
    }

    /// A room for a pair from the queue, both seated, its first game rated.
    fn open_match(&mut self, now: Instant, found: Match) -> Vec<Output> {
        let Match {
            variant,
            mode,
            a,
            b,
        } = found;
        let rules = RoomRules {
            variant,
            settings: mode,
            aim_aid: AimAid::FirstContact,
            reconnect_window: self.config.limits.reconnect_window,
            max_commands: self.config.limits.max_commands(variant),
        };
        let code = self.new_code();
        let (token_a, token_b) = (new_token(self.rng.as_mut()), new_token(self.rng.as_mut()));
        let seed = new_seed(self.rng.as_mut());
        let (mut room, mut out) = Room::create(
            now,
            code.clone(),
            rules,
            seed,
            a.conn,
            a.name.clone(),
            token_a,
        );
        let entry = room.join(now, b.conn, b.name.clone(), token_b);
        out.extend(entry.out);
        self.tokens
            .insert(TokenDigest::of(&token_a), (code.clone(), Seat::A));
        self.tokens
            .insert(TokenDigest::of(&token_b), (code.clone(), Seat::B));
        self.rooms.insert(room);
        self.set_room(a.conn, code.clone(), Role::Player(Seat::A));
        self.set_room(b.conn, code.clone(), Role::Player(Seat::B));
        self.lobby.list(
            code.clone(),
            Listing {
                variant,
                mode,
                host: Listed {
                    name: a.name.clone(),
                    key: Some(a.key),
                },
                guest: Some(Listed {
                    name: b.name.clone(),
                    key: Some(b.key),
                }),
                since: now,
                rated: true,
            },
        );
        out.push(RoomOutput::Store(StoreOp::RatedRoom {
            room: code.clone(),
            players: [a.key, b.key],
        }));
        self.rated.insert(
            code.clone(),
            RatedGame {
                keys: [a.key, b.key],
                names: [a.name, b.name],
                settled: false,
            },
        );
        let mut out = lift(out);
        out.extend(
            [a.conn, b.conn]
                .map(|conn| self.ratings_told(conn, &code))
                .into_iter()
                .flatten(),
        );
        out
    }

    /// Rates a quick-match room's first game once it is over with a winner: both ratings
    /// are stored, then both players are told.
    pub(super) fn settle_rating(&mut self, code: &RoomCode) -> Vec<Output> {
        let (Some(game), Some(room)) = (self.rated.get_mut(code), self.rooms.get(code)) else {
            return Vec::new();
        };
        if game.settled || room.game_number() != 1 {
            return Vec::new();
        }
        let Phase::Over { winner, .. } = room.game().phase() else {
            return Vec::new();
        };
        game.settled = true;
        let Some(winner) = *winner else {
            return Vec::new();
        };
        let (w, l) = (winner.index(), winner.other().index());
        let changes = self.ratings.rate(
            (game.keys[w], &game.names[w]),
            (game.keys[l], &game.names[l]),
        );
        let mut out = Vec::new();
        for (key, _, after) in &changes {
            out.push(Output::Room(RoomOutput::Store(StoreOp::Rating {
                key: *key,
                rating: after.clone(),
            })));
        }
        let seats = [winner, winner.other()];
        for (&conn, c) in &self.conns {
            if c.room.as_ref().is_some_and(|(r, _)| r == code) {
                for (seat, (_, before, after)) in seats.iter().zip(&changes) {
                    out.push(send(
                        conn,
                        ServerMessage::Rated {
                            seat: *seat,
                            before: before.shown(),
                            after: after.shown(),
                        },
                    ));
                }
            }
        }
        out
    }
}
