//! `splineskin serve [FILE] [--port N] [--host ADDR]`: the editor, a local web page that
//! opens a drawing, places and drags handles and shows the drawing follow live.
//! `splineskin serve --static-out DIR [--wasm FILE]` writes the same page as a static folder
//! whose requests the WebAssembly build answers in a Web Worker (no server).
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
    /// Instead of serving, write the editor as a static folder (its `index.html`, scripts and
    /// the WebAssembly module) that any static file host serves: opened from it, the page
    /// computes everything itself, in a Web Worker. The folder is created, or replaced if it
    /// holds an earlier static build.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["file", "port", "host"])]
    static_out: Option<PathBuf>,
    /// The WebAssembly module a static build carries. Default: $SPLINESKIN_WASM, else the one
    /// `tools/build-wasm` builds in this checkout's target folder
    /// (`target/wasm/wasm32-unknown-unknown/release/splineskin_wasm.wasm`).
    #[arg(long, value_name = "FILE", requires = "static_out")]
    wasm: Option<PathBuf>,
    /// The threaded WebAssembly module (shared memory, one thread per core) a static build
    /// carries for pages served cross-origin isolated (docs/webassembly.md, "Threads").
    /// Default: $SPLINESKIN_WASM_THREADS, else the one `tools/build-wasm` builds
    /// (`target/wasm-threads/wasm32-unknown-unknown/release/splineskin_wasm.wasm`); without
    /// one, the page computes on one thread per worker.
    #[arg(long, value_name = "FILE", requires = "static_out")]
    wasm_threads: Option<PathBuf>,
}

/// Where `tools/build-wasm` puts the module, under the target folder.
const BUILT_WASM: &str = "wasm/wasm32-unknown-unknown/release/splineskin_wasm.wasm";

/// Where `tools/build-wasm` puts the threaded module, under the target folder.
const BUILT_WASM_THREADS: &str = "wasm-threads/wasm32-unknown-unknown/release/splineskin_wasm.wasm";

/// Writes the static build into `dir` ([`assets::static_files`]) with the module `wasm` (or the
/// one found where `tools/build-wasm` puts it) and the threaded module `threads`, if any.
fn write_static(
    dir: &std::path::Path,
    wasm: Option<&std::path::Path>,
    threads: Option<&std::path::Path>,
) -> Result<()> {
    let wasm_path = match wasm {
        Some(path) => path.to_path_buf(),
        None => find_wasm("SPLINESKIN_WASM", BUILT_WASM).with_context(|| {
            format!(
                "{}: the WebAssembly module is not built: build it with tools/build-wasm \
                 (docs/webassembly.md), or name it with --wasm FILE",
                dir.display()
            )
        })?,
    };
    let wasm = read_module(&wasm_path)?;
    let threaded = threads.map(read_module).transpose()?;
    if dir.exists() {
        let earlier_build =
            dir.join("index.html").is_file() && dir.join(assets::STATIC_WASM_NAME).is_file();
        let empty = std::fs::read_dir(dir)
            .with_context(|| format!("{}: cannot read the folder", dir.display()))?
            .next()
            .is_none();
        if !earlier_build && !empty {
            anyhow::bail!(
                "{}: the folder exists and is not a static build of the editor (expected a new \
                 or empty folder, or an earlier build to replace)",
                dir.display()
            );
        }
    }
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create the folder", dir.display()))?;
    let files = assets::static_files(wasm, threaded);
    let paths: Vec<PathBuf> = files.iter().map(|(name, _)| dir.join(name)).collect();
    // The Catmull–Clark page's folder (`subdiv/`).
    for folder in paths
        .iter()
        .filter_map(|p| p.parent())
        .filter(|p| *p != dir)
    {
        std::fs::create_dir_all(folder)
            .with_context(|| format!("{}: cannot create the folder", folder.display()))?;
    }
    let writes: Vec<(&std::path::Path, &[u8])> = paths
        .iter()
        .zip(&files)
        .map(|(path, (_, bytes))| (path.as_path(), bytes.as_slice()))
        .collect();
    crate::output::write_all_atomic(&writes)?;
    // An earlier build's threaded module, not replaced by this build, would be run by the page.
    let stale = dir.join(assets::STATIC_WASM_THREADS_NAME);
    if !paths.contains(&stale) && stale.is_file() {
        std::fs::remove_file(&stale)
            .with_context(|| format!("{}: cannot remove the earlier build's", stale.display()))?;
    }
    let total: usize = files.iter().map(|(_, b)| b.len()).sum();
    println!(
        "{}: the editor without a server ({} files, {:.1} MB, the WebAssembly module {:.1} MB); \
         serve the folder with any static file server and open its index.html",
        dir.display(),
        files.len(),
        total as f64 / 1e6,
        files
            .iter()
            .find(|(name, _)| name == assets::STATIC_WASM_NAME)
            .map_or(0, |(_, b)| b.len()) as f64
            / 1e6
    );
    Ok(())
}

/// The bytes of the WebAssembly module at `path`, checked to be one.
fn read_module(path: &std::path::Path) -> Result<Vec<u8>> {
    let bytes = std::fs::read(path)
        .with_context(|| format!("{}: cannot read the WebAssembly module", path.display()))?;
    if !bytes.starts_with(b"\0asm") {
        anyhow::bail!(
            "{}: not a WebAssembly module (expected one built by tools/build-wasm)",
            path.display()
        );
    }
    Ok(bytes)
}

/// A WebAssembly module: `$variable`, else `built` under the target folder this executable was
/// built in, else under `./target`.
fn find_wasm(variable: &str, built: &str) -> Result<PathBuf> {
    if let Some(path) = std::env::var_os(variable) {
        return Ok(PathBuf::from(path));
    }
    let mut candidates = Vec::new();
    if let Ok(exe) = std::env::current_exe() {
        // target/{debug,release}/splineskin → target/
        if let Some(target) = exe.parent().and_then(|p| p.parent()) {
            candidates.push(target.join(built));
        }
    }
    candidates.push(PathBuf::from("target").join(built));
    candidates
        .iter()
        .find(|p| p.is_file())
        .cloned()
        .ok_or_else(|| {
            anyhow::anyhow!(
                "not found at {}",
                candidates
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(" nor at ")
            )
        })
}

pub fn run(args: Args) -> Result<()> {
    if let Some(dir) = &args.static_out {
        let threads = args.wasm_threads.clone().or_else(|| {
            find_wasm("SPLINESKIN_WASM_THREADS", BUILT_WASM_THREADS)
                .map_err(|e| {
                    eprintln!(
                        "note: {}: no threaded WebAssembly module ({e}; tools/build-wasm builds \
                         it): the page will compute on one thread per worker",
                        dir.display()
                    )
                })
                .ok()
        });
        return write_static(dir, args.wasm.as_deref(), threads.as_deref());
    }
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
