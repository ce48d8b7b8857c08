-- Rooms published in the lobby, with their players' Ed25519 keys by seat as far as they are
-- known (seat B's once it is taken), so an instance that restarts or takes a room over lists
-- it again, with the players' ratings.
CREATE TABLE listed_rooms (
    code TEXT PRIMARY KEY REFERENCES rooms (code),
    player_a BYTEA,
    player_b BYTEA
);
