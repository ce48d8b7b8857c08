-- Quick-match rooms, whose first game is rated: the two players' Ed25519 keys by seat, so an
-- instance that restarts or takes a room over rates its game as the one that opened it would.
CREATE TABLE rated_rooms (
    code TEXT PRIMARY KEY REFERENCES rooms (code),
    player_a BYTEA NOT NULL,
    player_b BYTEA NOT NULL
);
