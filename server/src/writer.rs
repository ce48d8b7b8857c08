//! What the writer thread (the one that sends every connection's outgoing messages) is
//! told, and a connection on a transport other than the QUIC endpoint's registering with it.

use std::sync::mpsc::Sender;
use std::time::Instant;

use crate::conn::{self, Outlet};
use crate::hub::Output;
use crate::limits::Limits;
use crate::output::ConnId;

/// What the writer thread is told.
pub(crate) enum WriterMsg {
    Register(ConnId, Outlet),
    Unregister(ConnId),
    /// What the hub (or a worker) made of one event: `read` is when the message it answers
    /// was read, for the server's time per command, and `handed` when it was given to the
    /// writer, for the writer's queue.
    Batch {
        out: Vec<Output>,
        read: Option<Instant>,
        handed: Instant,
    },
}

impl WriterMsg {
    /// A batch handed to the writer now.
    pub(crate) fn batch(out: Vec<Output>, read: Option<Instant>) -> WriterMsg {
        WriterMsg::Batch {
            out,
            read,
            handed: Instant::now(),
        }
    }
}

/// A game connection about to start on some transport other than the QUIC endpoint's: its
/// id, and what registers it with the writer thread and runs it.
pub(crate) struct Attach {
    id: ConnId,
    hub: conn::HubSender,
    writer: Sender<WriterMsg>,
    limits: Limits,
}

impl Attach {
    pub(crate) fn new(
        id: ConnId,
        hub: conn::HubSender,
        writer: Sender<WriterMsg>,
        limits: Limits,
    ) -> Attach {
        Attach {
            id,
            hub,
            writer,
            limits,
        }
    }

    /// Registers the connection's outgoing queue with the writer, runs it with
    /// [`conn::serve`] to its end, and unregisters it.
    pub(crate) async fn serve<T: conn::Transport>(
        self,
        link: &T,
        recv: impl tokio::io::AsyncRead + Unpin + Send,
        send: T::Send,
    ) {
        let (outlet, wiring) = conn::wire(self.id, self.hub, self.limits.outbound_queue);
        if self
            .writer
            .send(WriterMsg::Register(self.id, outlet))
            .is_err()
        {
            return;
        }
        conn::serve(wiring, link, recv, send, &self.limits).await;
        let _ = self.writer.send(WriterMsg::Unregister(self.id));
    }
}
