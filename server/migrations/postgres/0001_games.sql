-- The game log: the same tables as the SQLite store (server/src/store/sqlite.rs).
-- One row per room, one per game (its header and, once over, its result), one per command.
CREATE TABLE rooms (
    code TEXT PRIMARY KEY,
    meta BYTEA NOT NULL
);
CREATE TABLE games (
    room TEXT NOT NULL REFERENCES rooms (code),
    number BIGINT NOT NULL,
    header BYTEA NOT NULL,
    finished BOOLEAN NOT NULL,
    winner BIGINT,
    reason TEXT,
    finished_at BIGINT,
    PRIMARY KEY (room, number)
);
CREATE TABLE commands (
    room TEXT NOT NULL,
    number BIGINT NOT NULL,
    idx BIGINT NOT NULL,
    entry BYTEA NOT NULL,
    PRIMARY KEY (room, number, idx)
);
CREATE INDEX games_finished ON games (finished, finished_at);
