//! `splineskin serve [FILE] [--port N] [--host ADDR]`: the editor, a local web page that
//! opens a drawing, places and drags handles and shows the drawing follow live.
//!
//! ```text
//! page (web/, embedded)                         server (this module)
//!   open SVG / scene ───────── POST /api/open ──► Document: read by the library once
//!   add / move rest handles ── POST /api/rig ───► Puppet (editable PosedDrawing): weights + rig
//!                          ◄── operator O (f64) ─┘
//!   drag: points = O · vec(T), in the page, each frame
//!   mouse-up (flexible G¹) ─── POST /api/rigs/{id}/solve ─► warm-started flexible solve
//!   export ─────────────────── POST /api/documents/{id}/export ─► write_svg_view_box (styles kept;
//!                                                             viewBox kept or fitted to the art)
//!   after each edit ────────── POST /api/documents/{id}/outside ─► paths leaving the viewBox
//!   operator "family" ──────── POST /api/defop ─► Domain + train + DefOpRig (progress counted)
//!                          ◄── G_spline, ψ's centres (f64) ─┘
//!   drag: points = G_spline · ψ(Q), in the page, each frame
//! ```
//!
//! The editor's work is the library's [`splineskin_editor::Editor`], which documents the
//! routes; this module carries them over HTTP. Files: [`http`] (the router, its guard and job
//! slots), [`assets`] (the embedded page).
//!
//! The server listens on 127.0.0.1 unless `--host` names another address; it reads no file
//! but the one given on the command line (and the SVG a scene names next to it) and what the
//! page uploads.

mod assets;
pub mod http;

use std::io::Write;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::path::PathBuf;

use anyhow::{Context, Result};

use splineskin_editor::document::Document;

/// The default port (`--port`).
pub const DEFAULT_PORT: u16 = 7464;

#[derive(clap::Args)]
pub struct Args {
    /// The drawing to open: an SVG document or a scene (ours or the paper authors'
    /// `*-deformation.json`). Default: the bundled fish with its handles.
    file: Option<PathBuf>,
    /// The port to listen on; 0 lets the system choose a free one (the URL printed names it).
    #[arg(long, default_value_t = DEFAULT_PORT)]
    port: u16,
    /// The address to listen on. Default: 127.0.0.1 (this machine only). Any other address
    /// lets other machines use the editor, and the files it opens: only on a network you
    /// trust.
    #[arg(long)]
    host: Option<IpAddr>,
}

pub fn run(args: Args) -> Result<()> {
    let document = match &args.file {
        Some(path) => Document::from_path(path)?,
        None => Document::bundled()?,
    };
    for w in &document.info.warnings {
        eprintln!("warning: {w}");
    }
    let name = document.name.clone();
    let host = args.host.unwrap_or(IpAddr::V4(Ipv4Addr::LOCALHOST));
    if !host.is_loopback() {
        eprintln!(
            "warning: listening on {host}, not only this machine: anyone who can reach it can \
             use the editor and see the drawings it opens"
        );
    }
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .context("starting the server's runtime")?;
    runtime.block_on(async move {
        let listener = tokio::net::TcpListener::bind((host, args.port))
            .await
            .with_context(|| {
                format!(
                    "cannot listen on {}: {}",
                    SocketAddr::new(host, args.port),
                    "choose another port with --port (0: any free port)"
                )
            })?;
        let address = listener.local_addr().context("reading the bound address")?;
        let app = http::App::new(document, allowed_hosts(address));
        // The URL on stdout (tests read it), flushed before serving.
        let mut out = std::io::stdout().lock();
        writeln!(out, "splineskin editor: http://{address}/ ({name})")?;
        out.flush()?;
        drop(out);
        eprintln!("press Ctrl-C to stop");
        axum::serve(listener, http::router(app))
            .with_graceful_shutdown(async {
                let _ = tokio::signal::ctrl_c().await;
            })
            .await
            .context("serving")
    })
}

/// The `Host` header values a loopback server accepts (its own address under the names a
/// browser uses for it), or none (any) when listening beyond loopback.
fn allowed_hosts(address: SocketAddr) -> Vec<String> {
    if !address.ip().is_loopback() {
        return Vec::new();
    }
    let port = address.port();
    vec![
        format!("127.0.0.1:{port}"),
        format!("localhost:{port}"),
        format!("[::1]:{port}"),
        address.to_string(),
    ]
}

#[cfg(test)]
mod tests;
