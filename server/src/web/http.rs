//! The HTTP/1.1 side of the web listener: one request head read within a deadline and a size
//! limit, and the short answers. One request per connection (`Connection: close`).

use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt};

/// The most bytes a request head may take.
pub const MAX_HEAD: usize = 8 * 1024;

/// The most header lines a request head may have.
pub const MAX_HEADERS: usize = 32;

/// What the server needs of a request head.
#[derive(Debug, PartialEq, Eq)]
pub struct Head {
    /// `GET`, `HEAD`, or anything else (answered 405).
    pub method: String,
    /// The request target as sent (decoded later, by [`super::files::resolve`]).
    pub target: String,
    /// Header names (lowercase) and values, in order; values that are not UTF-8 are left out.
    pub headers: Vec<(String, String)>,
    /// Bytes read after the head (a WebSocket client's first frame, sent early).
    pub rest: Vec<u8>,
}

/// The first value of header `name` (lowercase) among `headers` (names lowercase, in order);
/// for answers read back too.
pub fn header<'a>(headers: &'a [(String, String)], name: &str) -> Option<&'a str> {
    headers
        .iter()
        .find(|(n, _)| n == name)
        .map(|(_, v)| v.as_str())
}

impl Head {
    /// The first value of header `name` (lowercase).
    pub fn header(&self, name: &str) -> Option<&str> {
        header(&self.headers, name)
    }

    /// Whether header `name` lists `token` (comma-separated, any case).
    pub fn has_token(&self, name: &str, token: &str) -> bool {
        self.headers
            .iter()
            .filter(|(n, _)| n == name)
            .flat_map(|(_, v)| v.split(','))
            .any(|t| t.trim().eq_ignore_ascii_case(token))
    }

    /// Whether the request says it has a body (this server takes none).
    pub fn has_body(&self) -> bool {
        self.header("transfer-encoding").is_some()
            || self
                .header("content-length")
                .is_some_and(|n| n.trim() != "0")
    }
}

/// Why no request head could be read.
#[derive(Debug, PartialEq, Eq)]
pub enum HeadError {
    /// The peer closed (or failed) before a whole head: nothing to answer.
    Closed,
    /// Not HTTP/1.x: 400.
    Malformed,
    /// Over [`MAX_HEAD`] bytes or [`MAX_HEADERS`] lines: 431.
    TooLarge,
}

/// Reads one request head (the caller bounds the time).
pub async fn read_head(stream: &mut (impl AsyncRead + Unpin)) -> Result<Head, HeadError> {
    let mut buf = Vec::with_capacity(1024);
    let mut chunk = [0u8; 1024];
    loop {
        let n = stream
            .read(&mut chunk)
            .await
            .map_err(|_| HeadError::Closed)?;
        if n == 0 {
            return Err(HeadError::Closed);
        }
        buf.extend_from_slice(&chunk[..n]);
        let mut headers = [httparse::EMPTY_HEADER; MAX_HEADERS];
        let mut req = httparse::Request::new(&mut headers);
        let within = buf.len().min(MAX_HEAD);
        match req.parse(&buf[..within]) {
            Ok(httparse::Status::Complete(len)) => {
                let head = Head {
                    method: req.method.unwrap_or("").to_string(),
                    target: req.path.unwrap_or("").to_string(),
                    headers: req
                        .headers
                        .iter()
                        .filter_map(|h| {
                            let value = std::str::from_utf8(h.value).ok()?;
                            Some((h.name.to_ascii_lowercase(), value.to_string()))
                        })
                        .collect(),
                    rest: buf[len..].to_vec(),
                };
                return Ok(head);
            }
            Ok(httparse::Status::Partial) if buf.len() >= MAX_HEAD => {
                return Err(HeadError::TooLarge)
            }
            Ok(httparse::Status::Partial) => {}
            Err(httparse::Error::TooManyHeaders) => return Err(HeadError::TooLarge),
            Err(_) => return Err(HeadError::Malformed),
        }
    }
}

/// Writes a complete response head (`Content-Length: len`, `Connection: close`) with the
/// extra header lines given.
pub async fn write_head(
    stream: &mut (impl AsyncWrite + Unpin),
    status: &str,
    content_type: &str,
    len: u64,
    extra: &[(&str, &str)],
) -> std::io::Result<()> {
    let mut head = format!(
        "HTTP/1.1 {status}\r\nContent-Type: {content_type}\r\nContent-Length: {len}\r\n\
         Connection: close\r\nX-Content-Type-Options: nosniff\r\n"
    );
    for (name, value) in extra {
        head.push_str(&format!("{name}: {value}\r\n"));
    }
    head.push_str("\r\n");
    stream.write_all(head.as_bytes()).await
}

/// Writes a short plain-text answer (`status` like `404 Not Found`); for a HEAD request
/// without its body.
pub async fn answer(
    stream: &mut (impl AsyncWrite + Unpin),
    status: &str,
    body: &str,
    with_body: bool,
    extra: &[(&str, &str)],
) -> std::io::Result<()> {
    let body = format!("{body}\n");
    write_head(
        stream,
        status,
        "text/plain; charset=utf-8",
        body.len() as u64,
        extra,
    )
    .await?;
    if with_body {
        stream.write_all(body.as_bytes()).await?;
    }
    stream.flush().await
}

#[cfg(test)]
mod tests {
    use super::*;

    async fn read(bytes: &[u8]) -> Result<Head, HeadError> {
        let (mut a, mut b) = tokio::io::duplex(64 * 1024);
        a.write_all(bytes).await.unwrap();
        drop(a);
        read_head(&mut b).await
    }

    #[tokio::test]
    async fn heads_parse_and_keep_what_follows() {
        let head =
            read(b"GET /ws HTTP/1.1\r\nHost: x\r\nConnection: keep-alive, Upgrade\r\n\r\nabc")
                .await
                .unwrap();
        assert_eq!(head.method, "GET");
        assert_eq!(head.target, "/ws");
        assert_eq!(head.header("host"), Some("x"));
        assert!(head.has_token("connection", "upgrade"));
        assert_eq!(head.rest, b"abc");
        assert!(!head.has_body());
    }

    #[tokio::test]
    async fn bad_and_large_heads_are_told_apart() {
        assert_eq!(read(b"GET / HTTP/1.1\r\n").await, Err(HeadError::Closed));
        assert_eq!(
            read(b"\x00\x01 nonsense\r\n\r\n").await,
            Err(HeadError::Malformed)
        );
        let mut big = b"GET / HTTP/1.1\r\nX: ".to_vec();
        big.extend(std::iter::repeat_n(b'a', MAX_HEAD));
        assert_eq!(read(&big).await, Err(HeadError::TooLarge));
        let mut many = b"GET / HTTP/1.1\r\n".to_vec();
        for i in 0..40 {
            many.extend(format!("X{i}: y\r\n").bytes());
        }
        many.extend(b"\r\n");
        assert_eq!(read(&many).await, Err(HeadError::TooLarge));
        let body = read(b"GET / HTTP/1.1\r\nContent-Length: 5\r\n\r\n")
            .await
            .unwrap();
        assert!(body.has_body());
    }
}
