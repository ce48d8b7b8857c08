//! One client connection: reads frames into the hub, writes what the hub sends. It only
//! moves bytes; every decision is the hub's.

use std::sync::mpsc::Sender;
use std::time::Duration;

use breakshot_shared::protocol::{
    decode_payload, encode_frame, payload_len, ClientMessage, ServerMessage, HEADER_LEN,
};
use tokio::sync::mpsc::UnboundedReceiver;

use crate::output::ConnId;

/// What the writer thread hands a connection.
#[derive(Debug)]
pub enum Outbound {
    Message(ServerMessage),
    Close(String),
}

/// What a connection tells the hub.
#[derive(Debug)]
pub enum HubEvent {
    Connected(ConnId),
    Message(ConnId, ClientMessage),
    Disconnected(ConnId),
    Shutdown,
}

/// Application close codes.
pub const CLOSE_NORMAL: u32 = 0;
pub const CLOSE_PROTOCOL: u32 = 1;

/// How long a client has to open its stream after connecting.
const OPEN_TIMEOUT: Duration = Duration::from_secs(10);
/// How long queued bytes get to reach the peer before a close.
const FLUSH_TIMEOUT: Duration = Duration::from_secs(2);

/// Runs one connection to its end. The hub has been told `Connected(id)` once the stream is
/// open, and is told `Disconnected(id)` at the end.
pub async fn serve(
    id: ConnId,
    conn: quinn::Connection,
    hub: Sender<HubEvent>,
    mut outbound: UnboundedReceiver<Outbound>,
) {
    let Ok(Ok((mut send, mut recv))) = tokio::time::timeout(OPEN_TIMEOUT, conn.accept_bi()).await
    else {
        conn.close(CLOSE_PROTOCOL.into(), b"no stream opened");
        return;
    };
    if hub.send(HubEvent::Connected(id)).is_err() {
        return;
    }
    let reader = {
        let hub = hub.clone();
        let conn = conn.clone();
        async move {
            loop {
                match read_message(&mut recv).await {
                    Ok(msg) => {
                        if hub.send(HubEvent::Message(id, msg)).is_err() {
                            break;
                        }
                    }
                    Err(ReadEnd::Closed) => break,
                    Err(ReadEnd::Malformed(why)) => {
                        tracing::info!(conn = id, %why, "closing connection: malformed frame");
                        conn.close(CLOSE_PROTOCOL.into(), why.as_bytes());
                        break;
                    }
                }
            }
        }
    };
    let writer = async {
        while let Some(out) = outbound.recv().await {
            match out {
                Outbound::Message(msg) => {
                    let frame = match encode_frame(&msg) {
                        Ok(f) => f,
                        Err(e) => {
                            tracing::error!(conn = id, error = %e, "cannot encode a message");
                            continue;
                        }
                    };
                    if send.write_all(&frame).await.is_err() {
                        break;
                    }
                }
                Outbound::Close(reason) => {
                    let _ = send.finish();
                    let _ = tokio::time::timeout(FLUSH_TIMEOUT, send.stopped()).await;
                    conn.close(CLOSE_NORMAL.into(), reason.as_bytes());
                    break;
                }
            }
        }
    };
    // Either side ending ends the connection.
    tokio::select! {
        _ = reader => {}
        _ = writer => {}
    }
    conn.close(CLOSE_NORMAL.into(), b"bye");
    let _ = hub.send(HubEvent::Disconnected(id));
}

enum ReadEnd {
    Closed,
    Malformed(String),
}

async fn read_message(recv: &mut quinn::RecvStream) -> Result<ClientMessage, ReadEnd> {
    let mut header = [0u8; HEADER_LEN];
    recv.read_exact(&mut header)
        .await
        .map_err(|_| ReadEnd::Closed)?;
    let len = payload_len(header).map_err(|e| ReadEnd::Malformed(e.to_string()))?;
    let mut payload = vec![0u8; len];
    recv.read_exact(&mut payload)
        .await
        .map_err(|_| ReadEnd::Closed)?;
    decode_payload(&payload).map_err(|e| ReadEnd::Malformed(e.to_string()))
}
