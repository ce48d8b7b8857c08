-- Which room each seat token (by its digest) belongs to, so a player reconnecting to any
-- server instance leads it to the room to take over. Rooms are owned through advisory locks
-- (server/src/store/postgres.rs), which need no table.
CREATE TABLE seats (
    digest BYTEA PRIMARY KEY,
    room TEXT NOT NULL REFERENCES rooms (code)
);
