// The page's side of Breakshot's network and page access, as a miniquad plugin: the game
// (WebAssembly, no wasm-bindgen) polls these functions once a frame. One table of sockets,
// each a WebTransport bidirectional stream or a WebSocket, with a queue of what arrived.
// See docs/web.md.
"use strict";
(function () {
    const OPENING = 0, OPEN = 1, ENDED = 2;
    const sockets = new Map();
    let next_id = 1;

    function bytes(ptr, len) {
        return new Uint8Array(wasm_memory.buffer, ptr, len);
    }
    function text(ptr, len) {
        return new TextDecoder().decode(bytes(ptr, len));
    }
    // Copies a string into the game's memory at ptr (capacity cap); returns its full length.
    function put_text(s, ptr, cap) {
        const encoded = new TextEncoder().encode(s);
        if (encoded.length <= cap) {
            bytes(ptr, encoded.length).set(encoded);
        }
        return encoded.length;
    }
    function end(sock, why) {
        if (sock.state !== ENDED) {
            sock.state = ENDED;
            sock.error = why || "connection closed";
        }
    }
    function hex_bytes(h) {
        const out = new Uint8Array(h.length / 2);
        for (let i = 0; i < out.length; i++) {
            out[i] = parseInt(h.substr(2 * i, 2), 16);
        }
        return out;
    }

    // A page served by the game server itself asks it for the current certificate hashes,
    // in case its link is older than a rotation (docs/web.md).
    async function current_hashes(url, hashes) {
        try {
            if (new URL(url).host !== window.location.host) {
                return hashes;
            }
            const answer = await fetch("/certificate.sha256", { cache: "no-store" });
            if (!answer.ok) {
                return hashes;
            }
            const listed = (await answer.text()).split("\n").map(function (h) { return h.trim(); })
                .filter(function (h) { return /^[0-9a-f]{64}$/.test(h); });
            return hashes.concat(listed.filter(function (h) { return hashes.indexOf(h) < 0; }));
        } catch (e) {
            return hashes;
        }
    }

    async function open_web_transport(sock, url, hashes) {
        try {
            hashes = await current_hashes(url, hashes);
            const options = { allowPooling: false, congestionControl: "low-latency" };
            if (hashes.length > 0) {
                options.serverCertificateHashes = hashes.map(function (h) {
                    return { algorithm: "sha-256", value: hex_bytes(h) };
                });
            }
            const wt = new WebTransport(url, options);
            sock.close = function () { try { wt.close(); } catch (e) { } };
            wt.closed.then(function () { end(sock, "the server closed the session"); },
                function (e) { end(sock, "WebTransport: " + e); });
            await wt.ready;
            const stream = await wt.createBidirectionalStream();
            const writer = stream.writable.getWriter();
            sock.send = function (data) {
                writer.write(data).catch(function (e) { end(sock, "WebTransport write: " + e); });
            };
            sock.state = OPEN;
            const reader = stream.readable.getReader();
            for (;;) {
                const { value, done } = await reader.read();
                if (done) break;
                sock.queue.push(value);
            }
            end(sock, "the server ended the stream");
        } catch (e) {
            end(sock, "WebTransport: " + e);
        }
    }

    function open_web_socket(sock, url) {
        let ws;
        try {
            ws = new WebSocket(url);
        } catch (e) {
            end(sock, "WebSocket: " + e);
            return;
        }
        ws.binaryType = "arraybuffer";
        sock.close = function () { try { ws.close(); } catch (e) { } };
        sock.send = function (data) { ws.send(data); };
        ws.onopen = function () { sock.state = OPEN; };
        ws.onmessage = function (event) {
            if (typeof event.data === "string") {
                end(sock, "the server sent text on the game's socket");
                ws.close();
                return;
            }
            sock.queue.push(new Uint8Array(event.data));
        };
        ws.onerror = function () { end(sock, "WebSocket error"); };
        ws.onclose = function (event) {
            end(sock, "WebSocket closed (" + event.code + (event.reason ? ": " + event.reason : "") + ")");
        };
    }

    const events = [];
    window.breakshotEvents = events;

    function register_plugin(importObject) {
        const env = importObject.env;
        // kind 0: WebTransport to url with the certificate hashes (hex, comma separated);
        // kind 1: WebSocket to url.
        env.bs_net_open = function (kind, url_ptr, url_len, hashes_ptr, hashes_len) {
            const id = next_id++;
            const sock = { state: OPENING, queue: [], error: "", send: function () { }, close: function () { } };
            sockets.set(id, sock);
            const url = text(url_ptr, url_len);
            if (kind === 0) {
                const hashes = text(hashes_ptr, hashes_len).split(",").filter(function (h) { return h.length === 64; });
                open_web_transport(sock, url, hashes);
            } else {
                open_web_socket(sock, url);
            }
            return id;
        };
        env.bs_net_send = function (id, ptr, len) {
            const sock = sockets.get(id);
            if (sock && sock.state === OPEN) {
                sock.send(bytes(ptr, len).slice());
            }
        };
        env.bs_net_close = function (id) {
            const sock = sockets.get(id);
            if (sock) {
                sock.close();
                sockets.delete(id);
            }
        };
        env.bs_net_state = function (id) {
            const sock = sockets.get(id);
            return sock ? sock.state : ENDED;
        };
        // The length of the next piece that arrived, or -1.
        env.bs_net_next_len = function (id) {
            const sock = sockets.get(id);
            return sock && sock.queue.length > 0 ? sock.queue[0].length : -1;
        };
        env.bs_net_take = function (id, ptr) {
            const sock = sockets.get(id);
            const piece = sock.queue.shift();
            bytes(ptr, piece.length).set(piece);
        };
        env.bs_net_error = function (id, ptr, cap) {
            const sock = sockets.get(id);
            return put_text(sock ? sock.error : "no such connection", ptr, cap);
        };
        env.bs_has_web_transport = function () {
            return typeof WebTransport !== "undefined" && window.isSecureContext ? 1 : 0;
        };
        // 0: location.href, 1: location.host, 2: location.protocol.
        env.bs_page = function (what, ptr, cap) {
            const values = [window.location.href, window.location.host, window.location.protocol];
            return put_text(values[what] || "", ptr, cap);
        };
        env.bs_random = function (ptr, len) {
            crypto.getRandomValues(bytes(ptr, len));
        };
        // The page's localStorage, which a browser may refuse (private windows, storage
        // turned off): then nothing is kept and nothing is found.
        env.bs_store_get = function (key_ptr, key_len, ptr, cap) {
            try {
                const value = window.localStorage.getItem(text(key_ptr, key_len));
                return value === null ? -1 : put_text(value, ptr, cap);
            } catch (e) {
                return -1;
            }
        };
        env.bs_store_set = function (key_ptr, key_len, ptr, len) {
            try {
                window.localStorage.setItem(text(key_ptr, key_len), text(ptr, len));
            } catch (e) { }
        };
        env.bs_store_remove = function (key_ptr, key_len) {
            try {
                window.localStorage.removeItem(text(key_ptr, key_len));
            } catch (e) { }
        };
        // An event for whoever watches the page (tests, the page's own status line).
        env.bs_report = function (ptr, len) {
            const line = text(ptr, len);
            events.push(line);
            if (line === "started") {
                window.breakshotStarted = true;
                document.getElementById("status").textContent = "";
            }
            console.log("breakshot: " + line);
            const status = document.getElementById("status");
            if (status && line.startsWith("status ")) {
                status.textContent = line.substring(7);
            }
        };
    }

    miniquad_add_plugin({ register_plugin: register_plugin, version: 1, name: "breakshot_net" });
})();
