//! Rooms run in parallel: while one room's shot is held on its worker (as long as a test
//! likes, standing in for a long simulation), other rooms play their shots and new players
//! are greeted and seated; the held shot then finishes with every hash agreeing. A room whose
//! work panics (a bug) is closed with word to its players, and costs no other room.

use std::sync::mpsc;
use std::sync::{Arc, Mutex};

use breakshot_server::RoomHook;
use breakshot_shared::protocol::{ClientMessage, RoomCode, ServerMessage};
use breakshot_tests::{
    break_shot, create_room, scratch, seated_pair, Player, Reads, TestServer, PATIENCE,
};

fn resolved(m: &ServerMessage) -> bool {
    matches!(m, ServerMessage::ShotResolved { .. })
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_room_held_in_a_long_shot_delays_no_other_room_and_no_new_player() -> anyhow::Result<()> {
    let data = scratch("parallel");
    let slow: Arc<Mutex<Option<RoomCode>>> = Arc::default();
    let (held_tx, mut held_rx) = tokio::sync::mpsc::unbounded_channel::<()>();
    let (release_tx, release_rx) = mpsc::channel::<()>();
    let release_rx = Mutex::new(release_rx);
    let mut config = TestServer::config(([127, 0, 0, 1], 0).into(), data.path());
    config.room_threads = 2;
    let hold = slow.clone();
    config.before_room_work = Some(RoomHook(Arc::new(move |room: &RoomCode| {
        if hold.lock().unwrap().as_ref() == Some(room) {
            let _ = held_tx.send(());
            // Bounded: a test that never releases fails instead of hanging.
            let _ = release_rx.lock().unwrap().recv_timeout(PATIENCE);
        }
    })));
    let server = TestServer::start_with(config).await?;

    let (mut a1, mut b1, room1) = seated_pair(&server.invite).await?;
    let (mut a2, mut b2, _room2) = seated_pair(&server.invite).await?;
    *slow.lock().unwrap() = Some(room1);

    let shot = break_shot(a1.game().expect("a game"));
    a1.send(shot).await?;
    tokio::time::timeout(PATIENCE, held_rx.recv())
        .await?
        .expect("the slow room's shot reached its worker");

    // Room 1 is now inside its shot. Room 2 plays a shot through to its result...
    let shot = break_shot(a2.game().expect("a game"));
    a2.send(shot).await?;
    for p in [&mut a2, &mut b2] {
        p.until("room 2's result", resolved).await?;
    }
    // ...and a new player is greeted and given a room.
    let mut newcomer = Player::connect(&server.invite).await?;
    create_room(&mut newcomer, "cy").await?;

    // Room 1's shot finishes, and both its players agree with the server.
    release_tx.send(())?;
    for p in [&mut a1, &mut b1] {
        p.until("room 1's result", resolved).await?;
    }
    for p in [&a1, &b1, &a2, &b2] {
        assert_eq!(p.replica.desyncs(), 0);
    }
    server.stop().await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_room_whose_work_panics_is_closed_and_costs_no_other_room() -> anyhow::Result<()> {
    let data = scratch("parallel-panic");
    let broken: Arc<Mutex<Option<RoomCode>>> = Arc::default();
    let mut config = TestServer::config(([127, 0, 0, 1], 0).into(), data.path());
    // One worker: if the panic took its thread, no other room could play.
    config.room_threads = 1;
    let hook_room = broken.clone();
    config.before_room_work = Some(RoomHook(Arc::new(move |room: &RoomCode| {
        if hook_room.lock().unwrap().as_ref() == Some(room) {
            panic!("a bug in room {room}, standing in for any");
        }
    })));
    let server = TestServer::start_with(config.clone()).await?;
    let (mut a1, mut b1, room1) = seated_pair(&server.invite).await?;
    let (mut a2, mut b2, _room2) = seated_pair(&server.invite).await?;
    let token = a1.client.token().expect("a seat token");
    let before = a1.game().expect("a game").clone();
    *broken.lock().unwrap() = Some(room1.clone());

    // Room 1's break panics on the worker: its players are told, and are out of it.
    a1.send(break_shot(&before)).await?;
    for p in [&mut a1, &mut b1] {
        match p.error().await? {
            ServerMessage::Error { message, .. } => {
                assert!(message.contains("internal error"), "{message}");
            }
            other => unreachable!("{other:?}"),
        }
    }
    // Room 2 plays on, on the same single worker.
    a2.send(break_shot(a2.game().expect("a game"))).await?;
    for p in [&mut a2, &mut b2] {
        p.until("room 2's result", resolved).await?;
    }
    drop((a1, b1, a2, b2));
    server.stop().await?;

    // Room 1's game was kept as last stored, and comes back with the server.
    *broken.lock().unwrap() = None;
    let server = TestServer::start_with(config).await?;
    let mut back = Player::connect(&server.invite).await?;
    back.send(ClientMessage::Rejoin { token }).await?;
    match back
        .until("the seat back", |m| {
            matches!(m, ServerMessage::Joined { .. })
        })
        .await?
    {
        ServerMessage::Joined { snapshot, .. } => {
            assert_eq!(snapshot.room, room1);
            assert_eq!(snapshot.game, before);
        }
        other => unreachable!("{other:?}"),
    }
    drop(back);
    server.stop().await
}
