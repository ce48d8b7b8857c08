//! `breakshot`: the game window, natively from the command line ([`cli`]) or in a browser
//! from the page's link (`web.rs`). Both only choose the first screen and open the window;
//! everything that can be computed without a window lives in the library.

#[cfg(not(target_arch = "wasm32"))]
mod cli;
mod ui;
#[cfg(target_arch = "wasm32")]
mod web;

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    cli::main()
}

#[cfg(target_arch = "wasm32")]
fn main() {
    web::main()
}
