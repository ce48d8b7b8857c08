-- Each player's Glicko-2 rating, by their Ed25519 public key (32 bytes), with the name they
-- last played a rated game under; written when a rated (quick-match) game ends.
CREATE TABLE ratings (
    player BYTEA PRIMARY KEY,
    name TEXT NOT NULL,
    rating DOUBLE PRECISION NOT NULL,
    deviation DOUBLE PRECISION NOT NULL,
    volatility DOUBLE PRECISION NOT NULL,
    games BIGINT NOT NULL
);
