//! The operator's view, on an address of its own (`breakshot-server --admin ADDR`): the
//! server's counters as Prometheus metrics (`GET /metrics`), liveness (`GET /healthz`),
//! readiness (`GET /readyz`, unready once draining) and a drain (`POST /drain`).
//!
//! The answers are pure functions of [`Stats`] ([`respond`]); [`serve`] is the thin HTTP/1.1
//! layer around them, with bounded requests: a head of at most [`MAX_HEAD`] bytes read within
//! [`READ_TIMEOUT`], one request per connection, and at most [`MAX_CLIENTS`] at once.

use std::fmt::Write as _;
use std::sync::atomic::AtomicUsize;
use std::sync::Arc;
use std::time::Duration;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::Semaphore;

use crate::stats::Stats;
use crate::timing::Histogram;

/// The longest request head read; a longer one is answered 431 and closed.
pub const MAX_HEAD: usize = 8 * 1024;
/// How long a client may take to send its request head.
pub const READ_TIMEOUT: Duration = Duration::from_secs(5);
/// Admin connections served at once; more wait for a place.
pub const MAX_CLIENTS: usize = 16;

/// An HTTP answer: status line, content type and body.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Response {
    /// The status code.
    pub status: u16,
    /// The `Content-Type`.
    pub content_type: &'static str,
    /// The body.
    pub body: String,
}

impl Response {
    fn text(status: u16, body: impl Into<String>) -> Response {
        Response {
            status,
            content_type: "text/plain; charset=utf-8",
            body: body.into(),
        }
    }
}

/// The answer to `method path` (the request line's first two words).
pub fn respond(method: &str, path: &str, stats: &Stats) -> Response {
    // A query string changes nothing here.
    let path = path.split('?').next().unwrap_or(path);
    match (method, path) {
        ("GET", "/metrics") => Response {
            status: 200,
            content_type: "text/plain; version=0.0.4; charset=utf-8",
            body: metrics(stats),
        },
        ("GET", "/healthz") => Response::text(200, "ok\n"),
        ("GET", "/readyz") if stats.is_draining() => Response::text(503, "draining\n"),
        ("GET", "/readyz") => Response::text(200, "ready\n"),
        ("POST", "/drain") => {
            stats.start_drain();
            Response::text(
                202,
                "draining: no new games; stopping when the games in play end\n",
            )
        }
        (_, "/metrics" | "/healthz" | "/readyz" | "/drain") => {
            Response::text(405, "method not allowed\n")
        }
        _ => Response::text(404, "not found: /metrics, /healthz, /readyz, POST /drain\n"),
    }
}

/// Every counter in the Prometheus text format (version 0.0.4).
pub fn metrics(stats: &Stats) -> String {
    let mut out = String::new();
    let get = |c: &AtomicUsize| Stats::get(c);
    gauge(
        &mut out,
        "breakshot_connections",
        "Connections open, handshakes included.",
        get(&stats.connections),
    );
    gauge(
        &mut out,
        "breakshot_handshakes",
        "Connections still in their handshake.",
        get(&stats.handshaking),
    );
    gauge(
        &mut out,
        "breakshot_players_connected",
        "Connections past their handshake (players and spectators).",
        get(&stats.connections).saturating_sub(get(&stats.handshaking)),
    );
    header(
        &mut out,
        "breakshot_rooms",
        "gauge",
        "Rooms open, by state.",
    );
    for (state, n) in [
        ("waiting", get(&stats.rooms_waiting)),
        ("playing", get(&stats.rooms_playing)),
        ("over", get(&stats.rooms_over)),
    ] {
        let _ = writeln!(out, "breakshot_rooms{{state=\"{state}\"}} {n}");
    }
    gauge(
        &mut out,
        "breakshot_hub_queue",
        "Events waiting for the hub thread.",
        get(&stats.hub_queue),
    );
    gauge(
        &mut out,
        "breakshot_hub_queue_peak",
        "The most events that have waited for the hub at once.",
        get(&stats.hub_queue_peak),
    );
    header(
        &mut out,
        "breakshot_refusals_total",
        "counter",
        "Connections and rooms refused, by reason.",
    );
    for (reason, n) in [
        ("connection_limit", get(&stats.refused)),
        ("address_share", get(&stats.refused_address)),
        ("flooding", get(&stats.flooding)),
        ("not_reading", get(&stats.too_slow)),
        ("draining", get(&stats.refused_draining)),
    ] {
        let _ = writeln!(out, "breakshot_refusals_total{{reason=\"{reason}\"}} {n}");
    }
    counter(
        &mut out,
        "breakshot_address_retries_total",
        "Connection attempts asked to prove their address first.",
        get(&stats.retried),
    );
    counter(
        &mut out,
        "breakshot_web_requests_total",
        "HTTP request heads read on the web listener (--web).",
        get(&stats.web_requests),
    );
    counter(
        &mut out,
        "breakshot_web_sockets_total",
        "WebSockets that finished their Noise handshake and became game connections.",
        get(&stats.web_sockets),
    );
    counter(
        &mut out,
        "breakshot_web_sockets_failed_total",
        "WebSockets closed before their Noise handshake was done.",
        get(&stats.web_sockets_failed),
    );
    counter(
        &mut out,
        "breakshot_webtransport_sessions_total",
        "WebTransport sessions (h3 on the UDP port) that became game connections.",
        get(&stats.webtransport_sessions),
    );
    counter(
        &mut out,
        "breakshot_webtransport_refused_total",
        "h3 connections refused: a failed HTTP/3 exchange, another path, or no stream in time.",
        get(&stats.webtransport_refused),
    );
    histogram(
        &mut out,
        "breakshot_command_seconds",
        "The server's time per applied command: read, queue, rules and simulation, durable write.",
        &stats.command_time,
    );
    histogram(
        &mut out,
        "breakshot_store_write_seconds",
        "Time per durable store write (one group commit).",
        &stats.store_write_time,
    );
    for (name, help, h) in [
        (
            "breakshot_read_seconds",
            "From a message's first byte on its stream to the message decoded.",
            &stats.read_time,
        ),
        (
            "breakshot_hub_wait_seconds",
            "From a message's frame read to the hub thread taking it up.",
            &stats.hub_wait,
        ),
        (
            "breakshot_hub_seconds",
            "The hub thread's time on one message.",
            &stats.hub_time,
        ),
        (
            "breakshot_worker_wait_seconds",
            "From a room lent out with a message to a worker starting on it.",
            &stats.worker_wait,
        ),
        (
            "breakshot_worker_seconds",
            "A worker's time on one room's message (rules and simulation).",
            &stats.worker_time,
        ),
        (
            "breakshot_writer_wait_seconds",
            "From results handed to the writer thread to the writer taking them up.",
            &stats.writer_wait,
        ),
        (
            "breakshot_send_wait_seconds",
            "From a message handed to its connection to its frame written on the stream.",
            &stats.send_wait,
        ),
    ] {
        histogram(&mut out, name, help, h);
    }
    header(
        &mut out,
        "breakshot_queue_players",
        "gauge",
        "Players waiting for a quick match, by game.",
    );
    let queued = stats.queued.lock().map(|q| q.clone()).unwrap_or_default();
    for (game, n) in queued {
        let _ = writeln!(out, "breakshot_queue_players{{game=\"{game}\"}} {n}");
    }
    gauge(
        &mut out,
        "breakshot_rooms_listed",
        "Rooms listed in the lobby (public rooms waiting, and quick-match games).",
        get(&stats.rooms_listed),
    );
    counter(
        &mut out,
        "breakshot_desyncs_reported_total",
        "Shots whose result a client computed differently from the server (ReportDesync).",
        get(&stats.desyncs_reported),
    );
    gauge(
        &mut out,
        "breakshot_draining",
        "1 while the server drains (opens no new game).",
        usize::from(stats.is_draining()),
    );
    out
}

fn header(out: &mut String, name: &str, kind: &str, help: &str) {
    let _ = writeln!(out, "# HELP {name} {help}\n# TYPE {name} {kind}");
}

fn gauge(out: &mut String, name: &str, help: &str, value: usize) {
    header(out, name, "gauge", help);
    let _ = writeln!(out, "{name} {value}");
}

fn counter(out: &mut String, name: &str, help: &str, value: usize) {
    header(out, name, "counter", help);
    let _ = writeln!(out, "{name} {value}");
}

/// Bucket edges 2^(1/2) apart (every fourth of the histogram's own), from 1 µs to about 34 s.
const BUCKET_STEP: usize = 4;

fn histogram(out: &mut String, name: &str, help: &str, h: &Histogram) {
    header(out, name, "histogram", help);
    let buckets = h.cumulative(BUCKET_STEP);
    let count = buckets.last().map_or(0, |b| b.1);
    for (edge, n) in &buckets {
        let _ = writeln!(out, "{name}_bucket{{le=\"{:e}\"}} {n}", edge.as_secs_f64());
    }
    let _ = writeln!(out, "{name}_bucket{{le=\"+Inf\"}} {count}");
    let _ = writeln!(out, "{name}_sum {:e}", h.sum().as_secs_f64());
    let _ = writeln!(out, "{name}_count {count}");
}

/// Serves the admin paths on `listener` until the task is dropped.
pub async fn serve(listener: TcpListener, stats: Arc<Stats>) {
    let places = Arc::new(Semaphore::new(MAX_CLIENTS));
    loop {
        let Ok((stream, _)) = listener.accept().await else {
            // Out of file descriptors or the like: wait a little rather than spin.
            tokio::time::sleep(Duration::from_millis(100)).await;
            continue;
        };
        let Ok(place) = places.clone().acquire_owned().await else {
            return;
        };
        let stats = stats.clone();
        tokio::spawn(async move {
            let _ = answer(stream, &stats).await;
            drop(place);
        });
    }
}

/// Reads one request head (bounded in size and time) and writes its answer.
async fn answer(mut stream: TcpStream, stats: &Stats) -> std::io::Result<()> {
    let head = match tokio::time::timeout(READ_TIMEOUT, read_head(&mut stream)).await {
        Ok(Ok(Some(head))) => head,
        Ok(Ok(None)) => {
            let too_long = Response::text(431, "request head too large\n");
            return write(&mut stream, &too_long).await;
        }
        Ok(Err(e)) => return Err(e),
        Err(_) => return Ok(()),
    };
    let mut words = head.split_whitespace();
    let response = match (words.next(), words.next()) {
        (Some(method), Some(path)) => respond(method, path, stats),
        _ => Response::text(400, "bad request\n"),
    };
    write(&mut stream, &response).await
}

/// The request head up to the blank line; `None` when it is longer than [`MAX_HEAD`].
async fn read_head(stream: &mut TcpStream) -> std::io::Result<Option<String>> {
    let mut buf = Vec::with_capacity(512);
    let mut chunk = [0u8; 1024];
    loop {
        if let Some(end) = find_blank_line(&buf) {
            return Ok(Some(String::from_utf8_lossy(&buf[..end]).into_owned()));
        }
        if buf.len() > MAX_HEAD {
            return Ok(None);
        }
        let n = stream.read(&mut chunk).await?;
        if n == 0 {
            // The client stopped sending: answer what came.
            return Ok(Some(String::from_utf8_lossy(&buf).into_owned()));
        }
        buf.extend_from_slice(&chunk[..n]);
    }
}

fn find_blank_line(buf: &[u8]) -> Option<usize> {
    buf.windows(4)
        .position(|w| w == b"\r\n\r\n")
        .or_else(|| buf.windows(2).position(|w| w == b"\n\n"))
}

async fn write(stream: &mut TcpStream, r: &Response) -> std::io::Result<()> {
    let reason = match r.status {
        200 => "OK",
        202 => "Accepted",
        400 => "Bad Request",
        404 => "Not Found",
        405 => "Method Not Allowed",
        431 => "Request Header Fields Too Large",
        503 => "Service Unavailable",
        _ => "",
    };
    let head = format!(
        "HTTP/1.1 {} {reason}\r\nContent-Type: {}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
        r.status,
        r.content_type,
        r.body.len()
    );
    stream.write_all(head.as_bytes()).await?;
    stream.write_all(r.body.as_bytes()).await?;
    stream.shutdown().await
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::Ordering;

    /// The value of the sample `series` (name and labels, as written) in a scrape.
    fn sample(text: &str, series: &str) -> Option<f64> {
        text.lines()
            .filter(|l| !l.starts_with('#'))
            .find_map(|l| l.strip_prefix(series)?.strip_prefix(' ')?.parse().ok())
    }

    #[test]
    fn metrics_carry_the_counters_in_the_text_format() {
        let stats = Stats::default();
        stats.connections.store(5, Ordering::Relaxed);
        stats.handshaking.store(2, Ordering::Relaxed);
        stats.rooms_playing.store(3, Ordering::Relaxed);
        stats.flooding.store(1, Ordering::Relaxed);
        stats.command_time.record(Duration::from_millis(2));
        stats.command_time.record(Duration::from_millis(30));
        let text = metrics(&stats);
        assert_eq!(sample(&text, "breakshot_connections"), Some(5.0));
        assert_eq!(sample(&text, "breakshot_players_connected"), Some(3.0));
        assert_eq!(
            sample(&text, "breakshot_rooms{state=\"playing\"}"),
            Some(3.0)
        );
        assert_eq!(
            sample(&text, "breakshot_rooms{state=\"waiting\"}"),
            Some(0.0)
        );
        assert_eq!(
            sample(&text, "breakshot_refusals_total{reason=\"flooding\"}"),
            Some(1.0)
        );
        assert_eq!(sample(&text, "breakshot_command_seconds_count"), Some(2.0));
        assert_eq!(
            sample(&text, "breakshot_command_seconds_bucket{le=\"+Inf\"}"),
            Some(2.0)
        );
        let sum = sample(&text, "breakshot_command_seconds_sum").expect("a sum");
        assert!((sum - 0.032).abs() < 1e-9, "{sum}");
        // Every sample line is `series value`, and every series has its TYPE line.
        for line in text.lines().filter(|l| !l.starts_with('#')) {
            let (series, value) = line.rsplit_once(' ').expect("series and value");
            assert!(value.parse::<f64>().is_ok(), "{line}");
            let family = series.split('{').next().unwrap_or(series);
            let family = ["_bucket", "_sum", "_count"]
                .iter()
                .find_map(|s| family.strip_suffix(s))
                .unwrap_or(family);
            assert!(
                text.contains(&format!("# TYPE {family} ")),
                "no TYPE for {family}"
            );
        }
    }

    #[test]
    fn readiness_turns_off_on_drain_and_liveness_stays() {
        let stats = Stats::default();
        assert_eq!(respond("GET", "/readyz", &stats).status, 200);
        assert_eq!(respond("GET", "/drain", &stats).status, 405);
        assert!(!stats.is_draining(), "a GET does not drain");
        assert_eq!(respond("POST", "/drain", &stats).status, 202);
        assert_eq!(respond("GET", "/readyz", &stats).status, 503);
        assert_eq!(respond("GET", "/healthz", &stats).status, 200);
        assert_eq!(sample(&metrics(&stats), "breakshot_draining"), Some(1.0));
    }

    #[test]
    fn unknown_paths_and_methods_are_refused() {
        let stats = Stats::default();
        assert_eq!(respond("GET", "/../etc/passwd", &stats).status, 404);
        assert_eq!(respond("DELETE", "/metrics", &stats).status, 405);
        assert_eq!(respond("GET", "/metrics?x=1", &stats).status, 200);
    }
}
