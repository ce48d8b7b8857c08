//! The Chrome DevTools Protocol over one WebSocket: numbered requests matched to their
//! answers, and the events that arrive in between kept in a queue per session, so that a page
//! can read its console messages whenever it next looks.
//!
//! Every read has a deadline: the socket's read timeout is set to what is left of it, and a
//! timed-out read leaves a partly read frame in tungstenite's buffer for the next read.

use std::collections::{HashMap, VecDeque};
use std::io::ErrorKind;
use std::net::{SocketAddr, TcpStream};
use std::time::{Duration, Instant};

use serde_json::{json, Value};
use tungstenite::protocol::WebSocketConfig;
use tungstenite::{Message, WebSocket};

use super::Error;

/// A session's queue keeps at most this many events; older ones are dropped, so a page that
/// logs without pause cannot grow the queue without bound while a test is not looking.
const QUEUE_LIMIT: usize = 10_000;

/// One event: its method (`Runtime.consoleAPICalled`) and parameters.
#[derive(Debug, Clone)]
pub(crate) struct Event {
    pub(crate) method: String,
    pub(crate) params: Value,
}

pub(crate) struct Cdp {
    socket: WebSocket<TcpStream>,
    next_id: u64,
    /// Events by session id; the browser's own session is the empty string.
    events: HashMap<String, VecDeque<Event>>,
    closed: Option<String>,
}

impl Cdp {
    /// Opens the browser's DevTools WebSocket at `ws://ADDR/PATH`.
    pub(crate) fn connect(addr: SocketAddr, path: &str, limit: Duration) -> Result<Cdp, String> {
        let stream =
            TcpStream::connect_timeout(&addr, limit).map_err(|e| format!("connecting: {e}"))?;
        let setup = |s: &TcpStream| -> std::io::Result<()> {
            s.set_nodelay(true)?;
            s.set_read_timeout(Some(limit))?;
            s.set_write_timeout(Some(limit))
        };
        setup(&stream).map_err(|e| format!("setting up the socket: {e}"))?;
        // Screenshots come as one base64 text message; a phone screen at three device pixels
        // per CSS pixel is several megabytes.
        let config = WebSocketConfig::default()
            .max_message_size(Some(256 << 20))
            .max_frame_size(Some(256 << 20));
        let url = format!("ws://{addr}{path}");
        let (socket, _) =
            tungstenite::client::client_with_config(url.as_str(), stream, Some(config))
                .map_err(|e| format!("the WebSocket handshake with {url}: {e}"))?;
        Ok(Cdp {
            socket,
            next_id: 1,
            events: HashMap::new(),
            closed: None,
        })
    }

    /// Sends `method` (to the page attached as `session`, or to the browser) and waits for its
    /// answer until `deadline`; events that arrive meanwhile are queued.
    pub(crate) fn call(
        &mut self,
        session: Option<&str>,
        method: &str,
        params: Value,
        deadline: Instant,
    ) -> Result<Value, Error> {
        let id = self.send(session, method, params)?;
        loop {
            match self.read(deadline)? {
                Some(Incoming::Answer { id: got, result }) if got == id => {
                    return result.map_err(|e| Error::Protocol(format!("{method}: {e}")));
                }
                // The answer to a call that timed out earlier: nobody waits for it any more.
                Some(_) => {}
                None => {
                    return Err(Error::Timeout(format!(
                        "an answer to {method} from the browser"
                    )))
                }
            }
        }
    }

    /// Sends `method` without waiting for its answer (closing the browser, whose answer may
    /// never come).
    pub(crate) fn send(
        &mut self,
        session: Option<&str>,
        method: &str,
        params: Value,
    ) -> Result<u64, Error> {
        if let Some(why) = &self.closed {
            return Err(Error::Closed(why.clone()));
        }
        let id = self.next_id;
        self.next_id += 1;
        let mut message = json!({ "id": id, "method": method, "params": params });
        if let Some(session) = session {
            message["sessionId"] = json!(session);
        }
        if let Err(e) = self.socket.send(Message::text(message.to_string())) {
            return Err(self.close(format!("sending {method}: {e}")));
        }
        Ok(id)
    }

    /// Waits until `deadline` for a message, then reads and queues what follows at once (so
    /// that one look sees a burst of events), but never past `deadline`, so that a page that
    /// logs without pause cannot keep this reading forever.
    pub(crate) fn pump(&mut self, deadline: Instant) -> Result<(), Error> {
        let mut until = deadline;
        while self.read(until)?.is_some() {
            let now = Instant::now();
            if now >= deadline {
                break;
            }
            until = (now + Duration::from_millis(2)).min(deadline);
        }
        Ok(())
    }

    /// Takes the events queued for `session` (the empty string is the browser's).
    pub(crate) fn take_events(&mut self, session: &str) -> VecDeque<Event> {
        self.events.remove(session).unwrap_or_default()
    }

    /// Reads one message, queueing it if it is an event; `None` when `deadline` passed first.
    fn read(&mut self, deadline: Instant) -> Result<Option<Incoming>, Error> {
        if let Some(why) = &self.closed {
            return Err(Error::Closed(why.clone()));
        }
        // A zero timeout means "block forever" to the socket: look for at least a moment.
        let left = deadline
            .saturating_duration_since(Instant::now())
            .max(Duration::from_millis(1));
        if let Err(e) = self.socket.get_ref().set_read_timeout(Some(left)) {
            return Err(self.close(format!("setting the read timeout: {e}")));
        }
        let text = match self.socket.read() {
            Ok(Message::Text(text)) => text,
            Ok(Message::Close(frame)) => {
                return Err(self.close(format!("the browser closed its connection ({frame:?})")))
            }
            // Pings are answered by tungstenite; the protocol sends no binary messages.
            Ok(_) => return Ok(Some(Incoming::Other)),
            Err(tungstenite::Error::Io(e))
                if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) =>
            {
                return Ok(None)
            }
            Err(e) => return Err(self.close(format!("reading from the browser: {e}"))),
        };
        let message: Value = serde_json::from_str(text.as_str())
            .map_err(|e| Error::Protocol(format!("a message that is not JSON ({e}): {text}")))?;
        if let Some(id) = message.get("id").and_then(Value::as_u64) {
            let result = match message.get("error") {
                Some(error) => Err(error
                    .get("message")
                    .and_then(Value::as_str)
                    .map_or_else(|| error.to_string(), str::to_string)),
                None => Ok(message.get("result").cloned().unwrap_or(Value::Null)),
            };
            return Ok(Some(Incoming::Answer { id, result }));
        }
        if let Some(method) = message.get("method").and_then(Value::as_str) {
            let session = message
                .get("sessionId")
                .and_then(Value::as_str)
                .unwrap_or("")
                .to_string();
            let queue = self.events.entry(session).or_default();
            if queue.len() == QUEUE_LIMIT {
                queue.pop_front();
            }
            queue.push_back(Event {
                method: method.to_string(),
                params: message.get("params").cloned().unwrap_or(Value::Null),
            });
        }
        Ok(Some(Incoming::Other))
    }

    /// Marks the connection unusable; every later call fails with `why`.
    fn close(&mut self, why: String) -> Error {
        self.closed = Some(why.clone());
        Error::Closed(why)
    }
}

enum Incoming {
    Answer {
        id: u64,
        result: Result<Value, String>,
    },
    Other,
}
