//! Why a connection failed or ended: the one error of the player's network side, shared by
//! the core and its drivers.

use breakshot_shared::protocol::FrameError;
use thiserror::Error;

#[derive(Clone, Debug, Error, PartialEq)]
/// Why a connection failed or ended.
pub enum NetError {
    #[error("cannot resolve {0}")]
    /// The server's name did not resolve.
    Resolve(String),
    #[error("cannot connect: {0}")]
    /// No connection could be made.
    Connect(String),
    #[error(
        "this invite's fingerprint does not match the server: ask the host for a fresh invite"
    )]
    /// The server's certificate is not the one the invite names.
    WrongFingerprint,
    #[error("this link's key does not match the server: ask the host for a fresh link")]
    /// The server of a page's WebSocket does not hold the key the link names.
    WrongKey,
    #[error("connection lost: {0}")]
    /// The connection dropped.
    Lost(String),
    #[error("the server refused us: {0}")]
    /// The server answered and refused us.
    Rejected(String),
    #[error("bad frame from the server: {0}")]
    /// A frame from the server could not be read.
    Frame(String),
    #[error("the server sent {0} before Welcome")]
    /// The server's first answer was not `Welcome`.
    Handshake(String),
    #[error(
        "cannot reach the game at {tried} ({why}): check the address and the port, that the \
         host's game is running, and that its UDP port is open in the host's firewall (and \
         forwarded on its router when playing over the internet)"
    )]
    /// The first connection found no server at any address the invite names.
    Unreachable {
        /// The addresses tried, as the invite names them.
        tried: String,
        /// What the last attempt met.
        why: String,
    },
}

impl NetError {
    /// The server answered and will not have us (or is not the server the invite names):
    /// asking again cannot change the answer.
    pub fn is_refusal(&self) -> bool {
        matches!(
            self,
            NetError::Rejected(_) | NetError::WrongFingerprint | NetError::WrongKey
        )
    }
}

impl From<FrameError> for NetError {
    fn from(e: FrameError) -> NetError {
        NetError::Frame(e.to_string())
    }
}
