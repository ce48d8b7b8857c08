-- The shot clock of each game's current turn, the latest only, so a restarted server gives
-- the player to move what they had left: `left_ms` when written at `at_ms` (Unix
-- milliseconds, the store's clock), running or stopped.
CREATE TABLE clocks (
    room TEXT NOT NULL,
    number BIGINT NOT NULL,
    turn BIGINT NOT NULL,
    left_ms BIGINT NOT NULL,
    running BOOLEAN NOT NULL,
    at_ms BIGINT NOT NULL,
    PRIMARY KEY (room, number)
);
