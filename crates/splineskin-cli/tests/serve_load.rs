//! `splineskin serve` under load and faults, on loopback: [`CLIENTS`] editors at once, each
//! [`ROUNDS`] times opening a drawing, rigging it, solving a pose, asking a weight grid and
//! exporting; meanwhile slow uploads, requests abandoned, bodies at and over the upload
//! limit and garbage. Then the heavy routes ([`HEAVY_CLIENTS`] editors: bounded biharmonic
//! rigs, refinement, operator training, Lottie, Catmull–Clark rigs) and precomputations whose
//! clients leave mid-job, which must end and free their slot. Every answer must be 2xx, 4xx (with a message) or 503; the process must
//! still be serving at the end, with every job slot free, and its peak memory (`VmHWM`) below
//! [`PEAK_MEMORY`]. Prints the count and p50/p95 latency per route, and the peak memory.
//!
//! The store keeps [`splineskin_editor::store::MAX_DOCUMENTS`] documents and
//! [`splineskin_editor::store::MAX_RIGS`] rigs: with more editors than that, a client's
//! document or rig is often dropped before it asks for it again, and the answer is then a 404
//! naming it (counted, not an error): that is what bounds the memory.

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Write};
use std::net::SocketAddr;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use http_body_util::{BodyExt, Full};
use hyper::body::Bytes;
use splineskin_editor::document::MAX_UPLOAD_BYTES;
use splineskin_editor::store::MAX_RIGS;

/// Editors at once: 32.
const CLIENTS: usize = 32;

/// Rounds of requests per editor: 50 (each round one request of every kind).
const ROUNDS: usize = 50;

/// Editors at once on the heavy routes (bounded biharmonic rigs, refinement, operator
/// training, Lottie export, Catmull–Clark rigs): 4, twice the server's job slots.
const HEAVY_CLIENTS: usize = 4;

/// Rounds of the heavy routes per editor: 3.
const HEAVY_ROUNDS: usize = 3;

/// Precomputations abandoned mid-job (their connection dropped while they run or wait for a
/// slot): 3.
const ABANDONED: usize = 3;

/// The Catmull–Clark cage the heavy clients rig: the bundled tube.
const TUBE: &str = include_str!("../../splineskin/assets/subdiv/tube.obj");

/// Largest peak resident memory of the server allowed: 1 GiB (measured: see the test's
/// output; the store's limits bound it whatever the number of clients).
const PEAK_MEMORY: u64 = 1 << 30;

/// A small drawing each editor opens: a rect, a circle and a stroked curve.
const SVG: &str = "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 100 100\">\
    <rect x=\"10\" y=\"10\" width=\"40\" height=\"30\" fill=\"navy\"/>\
    <circle cx=\"70\" cy=\"60\" r=\"15\" fill=\"gold\"/>\
    <path d=\"M10 80 C30 60 60 95 90 80\" fill=\"none\" stroke=\"black\" stroke-width=\"3\"/></svg>";

/// One answer: status, body, the rig id header if any.
struct Answer {
    status: u16,
    body: Vec<u8>,
    rig: Option<String>,
}

impl Answer {
    /// A 200 with no body (what a check of the client's own records).
    fn ok() -> Answer {
        Answer {
            status: 200,
            body: Vec::new(),
            rig: None,
        }
    }
}

/// The server: its process and address.
struct Server {
    child: Child,
    addr: SocketAddr,
}

impl Server {
    /// Starts `splineskin serve --port 0` and reads the address it prints.
    fn start() -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_splineskin"))
            .args(["serve", "--port", "0"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start splineskin serve");
        let stdout = child.stdout.take().unwrap();
        let mut lines = BufReader::new(stdout).lines();
        let addr = loop {
            let line = lines.next().expect("serve printed no URL").unwrap();
            if let Some(at) = line.find("http://") {
                let rest = &line[at + 7..];
                let end = rest.find('/').unwrap_or(rest.len());
                break rest[..end].parse().expect("an address");
            }
        };
        // Keep reading its stdout, so that it never blocks on a full pipe.
        std::thread::spawn(move || for _ in lines {});
        Server { child, addr }
    }

    /// Peak resident memory (`VmHWM` of /proc), bytes.
    fn peak_memory(&self) -> u64 {
        let status = std::fs::read_to_string(format!("/proc/{}/status", self.child.id())).unwrap();
        let line = status.lines().find(|l| l.starts_with("VmHWM:")).unwrap();
        let kib: u64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
        kib * 1024
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Sends one request on a connection of its own.
async fn send(
    addr: SocketAddr,
    method: &str,
    target: &str,
    body: Vec<u8>,
) -> Result<Answer, String> {
    send_with(addr, method, target, body, &[]).await
}

/// [`send`] with more headers.
async fn send_with(
    addr: SocketAddr,
    method: &str,
    target: &str,
    body: Vec<u8>,
    headers: &[(&str, &str)],
) -> Result<Answer, String> {
    let stream = tokio::net::TcpStream::connect(addr)
        .await
        .map_err(|e| e.to_string())?;
    let io = hyper_util::rt::TokioIo::new(stream);
    let (mut sender, connection) = hyper::client::conn::http1::handshake(io)
        .await
        .map_err(|e| e.to_string())?;
    tokio::task::spawn_local(connection);
    let request = hyper::Request::builder()
        .method(method)
        .uri(target)
        .header("host", addr.to_string())
        .header("x-splineskin", "1")
        .header("x-file-name", "load.svg");
    let request = headers
        .iter()
        .fold(request, |r, (k, v)| r.header(*k, *v))
        .body(Full::new(Bytes::from(body)))
        .map_err(|e| e.to_string())?;
    let response = sender
        .send_request(request)
        .await
        .map_err(|e| e.to_string())?;
    let status = response.status().as_u16();
    let rig = response
        .headers()
        .get("x-splineskin-rig")
        .and_then(|v| v.to_str().ok())
        .map(str::to_string);
    let body = response
        .into_body()
        .collect()
        .await
        .map_err(|e| e.to_string())?
        .to_bytes()
        .to_vec();
    Ok(Answer { status, body, rig })
}

/// What the clients saw: per route, the latencies (ms) and statuses; and every answer outside
/// 2xx/4xx/503 or 4xx without a message.
#[derive(Default)]
struct Tally {
    latencies: BTreeMap<&'static str, Vec<f64>>,
    statuses: BTreeMap<(&'static str, u16), usize>,
    wrong: Vec<String>,
}

impl Tally {
    fn record(&mut self, route: &'static str, started: Instant, answer: &Result<Answer, String>) {
        let ms = started.elapsed().as_secs_f64() * 1e3;
        self.latencies.entry(route).or_default().push(ms);
        match answer {
            Ok(a) => {
                *self.statuses.entry((route, a.status)).or_default() += 1;
                let allowed = (200..300).contains(&a.status)
                    || (400..500).contains(&a.status)
                    || a.status == 503;
                if !allowed || ((400..500).contains(&a.status) && a.body.is_empty()) {
                    self.wrong.push(format!(
                        "{route}: {} {}",
                        a.status,
                        String::from_utf8_lossy(&a.body)
                    ));
                }
            }
            Err(e) => self.wrong.push(format!("{route}: no answer: {e}")),
        }
    }
}

impl Tally {
    /// Adds `other`'s counts and latencies.
    fn merge(&mut self, other: Tally) {
        for (route, mut l) in other.latencies {
            self.latencies.entry(route).or_default().append(&mut l);
        }
        for (key, n) in other.statuses {
            *self.statuses.entry(key).or_default() += n;
        }
        self.wrong.extend(other.wrong);
    }
}

/// Per route: requests, p50 and p95 latency, statuses.
fn table(tally: &mut Tally) -> String {
    let mut out = String::new();
    for (route, latencies) in &mut tally.latencies {
        let n = latencies.len();
        let (p50, p95) = (quantile(latencies, 0.5), quantile(latencies, 0.95));
        let statuses: Vec<String> = tally
            .statuses
            .iter()
            .filter(|((r, _), _)| r == route)
            .map(|((_, s), n)| format!("{s}×{n}"))
            .collect();
        out.push_str(&format!(
            "  {route:<20} {n:>5} requests  p50 {p50:>8.2} ms  p95 {p95:>8.2} ms  ({})\n",
            statuses.join(", ")
        ));
    }
    out
}

/// The pose of client `k` in round `round`: a small turn of handle 1.
fn pose(k: usize, round: usize) -> serde_json::Value {
    let (s, c) = (0.01 * (k + round) as f64).sin_cos();
    serde_json::json!([[1, 0, 0, 1, 0, 0], [c, s, -s, c, 5, -3], [1, 0, 0, 1, 0, 4]])
}

/// Opens [`SVG`] and rigs it (three Shepard handles): the document's and the rig's ids.
async fn open_and_rig(addr: SocketAddr, k: usize, tally: &mut Tally) -> Option<(String, String)> {
    let t = Instant::now();
    let opened = send(addr, "POST", "/api/open", SVG.as_bytes().to_vec()).await;
    tally.record("open", t, &opened);
    let info: serde_json::Value = serde_json::from_slice(&opened.ok()?.body).ok()?;
    let doc = info["id"].as_str()?.to_string();
    let mut scene = info["scene"].clone();
    scene["handles"] = serde_json::json!([[20, 20], [80, 30], [40, 85]]);
    scene["pose"] = pose(k, 0);
    scene["weights"]["family"] = "shepard".into();
    let body = serde_json::json!({ "document": doc, "scene": scene }).to_string();
    let t = Instant::now();
    let rigged = send(addr, "POST", "/api/rig", body.into_bytes()).await;
    tally.record("rig", t, &rigged);
    Some((doc, rigged.ok()?.rig?))
}

/// One editor's rounds: each a pose solved, a weight grid and an export, after opening and
/// rigging a drawing anew (`steady` false) or only once, before the first (`steady` true).
async fn client(addr: SocketAddr, k: usize, steady: bool) -> Tally {
    let mut tally = Tally::default();
    let mut kept = None;
    for round in 0..ROUNDS {
        let ids = match kept.clone() {
            Some(ids) if steady => Some(ids),
            _ => open_and_rig(addr, k, &mut tally).await,
        };
        let Some((doc, rig)) = ids else { continue };
        kept = Some((doc.clone(), rig.clone()));
        let pose = pose(k, round);
        let body = serde_json::json!({ "pose": pose }).to_string();
        let t = Instant::now();
        let target = format!("/api/rigs/{rig}/solve");
        let solved = send(addr, "POST", &target, body.into_bytes()).await;
        tally.record("solve", t, &solved);
        let t = Instant::now();
        let grid =
            format!("/api/rigs/{rig}/weights?handle=1&x0=0&y0=0&x1=100&y1=100&width=32&height=32");
        let weights = send(addr, "GET", &grid, Vec::new()).await;
        tally.record("weights", t, &weights);
        let Some(mut body) = solved.ok().filter(|a| a.status == 200).map(|a| a.body) else {
            continue;
        };
        for t in pose.as_array().unwrap() {
            for v in t.as_array().unwrap() {
                body.extend_from_slice(&v.as_f64().unwrap().to_le_bytes());
            }
        }
        let t = Instant::now();
        let target = format!("/api/documents/{doc}/export?viewbox=keep&rig={rig}");
        let exported = send(addr, "POST", &target, body).await;
        tally.record("export", t, &exported);
    }
    tally
}

/// One editor's rounds on the heavy routes: open, a bounded biharmonic rig, a refinement of a
/// bend, an operator trained (Rigid ARAP, 10 samples), a Lottie export of a two-key timeline,
/// and a Catmull–Clark rig of the tube.
async fn heavy_client(addr: SocketAddr, k: usize) -> Tally {
    let mut tally = Tally::default();
    for round in 0..HEAVY_ROUNDS {
        let t = Instant::now();
        let opened = send(addr, "POST", "/api/open", SVG.as_bytes().to_vec()).await;
        tally.record("open", t, &opened);
        let Some(info) = opened
            .ok()
            .and_then(|a| serde_json::from_slice::<serde_json::Value>(&a.body).ok())
        else {
            continue;
        };
        let doc = info["id"].as_str().unwrap_or("").to_string();
        let mut scene = info["scene"].clone();
        scene["handles"] = serde_json::json!([[20, 20], [80, 30], [40, 85]]);
        scene["pose"] = pose(k, round);
        scene["weights"] = serde_json::json!({"family": "bbw"});
        let body = serde_json::json!({ "document": doc, "scene": scene }).to_string();
        let t = Instant::now();
        let rigged = send(addr, "POST", "/api/rig", body.into_bytes()).await;
        tally.record("rig (bbw)", t, &rigged);
        if let Some(rig) = rigged.ok().and_then(|a| a.rig) {
            let body =
                serde_json::json!({"scene": scene, "poses": [pose(k, round)], "tolerance": 1e-4});
            let t = Instant::now();
            let target = format!("/api/rigs/{rig}/refine");
            let refined = send(addr, "POST", &target, body.to_string().into_bytes()).await;
            tally.record("refine", t, &refined);
        }
        let mut operator = scene.clone();
        operator["weights"] = serde_json::json!({"family": "defop-arap", "samples": 10});
        operator["pose"] = serde_json::json!(vec![[1, 0, 0, 1, 0, 0]; 3]);
        let body = serde_json::json!({ "document": doc, "scene": operator }).to_string();
        let t = Instant::now();
        let trained = send(addr, "POST", "/api/defop", body.into_bytes()).await;
        tally.record("defop", t, &trained);
        let mut animated = scene.clone();
        animated["weights"] = serde_json::json!({"family": "shepard"});
        animated["animation"] = serde_json::json!({"fps": 10.0, "keyframes": [
            {"time": 0.0, "pose": pose(k, 0)},
            {"time": 1.0, "pose": pose(k, round + 20)}
        ]});
        let t = Instant::now();
        let target = format!("/api/documents/{doc}/lottie");
        let lottie = send(addr, "POST", &target, animated.to_string().into_bytes()).await;
        tally.record("lottie", t, &lottie);
        let body = serde_json::json!({"name": "tube.obj", "obj": TUBE, "level": 1, "scene": {
            "handles": [{"position": [0.5, 0.0, 0.0]}, {"position": [7.5, 0.0, 0.0]}]
        }});
        let t = Instant::now();
        let subdiv = send(
            addr,
            "POST",
            "/api/subdiv/rig",
            body.to_string().into_bytes(),
        )
        .await;
        tally.record("subdiv rig", t, &subdiv);
    }
    tally
}

/// Bounded biharmonic rigs whose clients leave while they run: each request followed as a
/// job (`x-splineskin-job`), its connection dropped after 30 ms. Every job must end (its
/// progress `{"stage": null}`) within 120 s, its slot free: a rig asked after them answers.
/// Records, per job, the time from its request until it is gone.
async fn abandoned_jobs(addr: SocketAddr) -> Tally {
    let mut tally = Tally::default();
    let opened = send(addr, "POST", "/api/open", SVG.as_bytes().to_vec()).await;
    let info: serde_json::Value = serde_json::from_slice(&opened.expect("open").body).unwrap();
    // Each job its own pins (nothing cached from another), its client gone after 30 ms: a
    // bounded biharmonic precomputation takes longer (hundreds of ms on this drawing).
    let body = |i: usize| {
        let mut scene = info["scene"].clone();
        scene["handles"] = serde_json::json!([[20, 20], [80, 30], [40, 85], [60, 50 + i]]);
        scene["pose"] = serde_json::json!(vec![[1, 0, 0, 1, 0, 0]; 4]);
        scene["weights"] = serde_json::json!({"family": "bbw"});
        serde_json::json!({ "document": info["id"], "scene": scene }).to_string()
    };
    let started = Instant::now();
    let jobs: Vec<String> = (0..ABANDONED).map(|i| format!("abandoned-{i}")).collect();
    // Requests left unanswered when their client went (the test would prove nothing if every
    // one had been answered first).
    let mut left = 0;
    for (i, job) in jobs.iter().enumerate() {
        let headers = [("x-splineskin-job", job.as_str())];
        let request = send_with(addr, "POST", "/api/rig", body(i).into_bytes(), &headers);
        let answered = tokio::time::timeout(Duration::from_millis(30), request).await;
        left += usize::from(answered.is_err());
    }
    assert!(left > 0, "every abandoned rig was answered within 30 ms");
    for job in &jobs {
        loop {
            let answer = send(addr, "GET", &format!("/api/progress/{job}"), Vec::new()).await;
            let stage = answer
                .ok()
                .and_then(|a| serde_json::from_slice::<serde_json::Value>(&a.body).ok())
                .map(|v| v["stage"].clone());
            if stage == Some(serde_json::Value::Null) {
                break;
            }
            assert!(
                started.elapsed() < Duration::from_secs(120),
                "{job} still runs"
            );
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
        tally.record("abandoned job gone", started, &Ok(Answer::ok()));
    }
    let t = Instant::now();
    let again = send(addr, "POST", "/api/rig", body(ABANDONED).into_bytes()).await;
    assert_eq!(again.as_ref().map(|a| a.status).ok(), Some(200));
    tally.record("rig (bbw) after", t, &again);
    tally
}

/// The faults, while the clients run: a slow upload, rigs abandoned mid-job, bodies at and
/// over the limit, garbage.
async fn faults(addr: SocketAddr) -> Tally {
    let mut tally = Tally::default();
    // A slow upload: the headers, then one byte every 50 ms for 2 s, then the connection
    // dropped. The other clients go on meanwhile.
    let slow = std::thread::spawn(move || {
        let mut stream = std::net::TcpStream::connect(addr).unwrap();
        let head = format!(
            "POST /api/open HTTP/1.1\r\nhost: {addr}\r\nx-splineskin: 1\r\ncontent-length: 100000\r\n\r\n"
        );
        stream.write_all(head.as_bytes()).unwrap();
        for _ in 0..40 {
            if stream.write_all(b" ").is_err() {
                break;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    });
    // Rigs abandoned right after they are sent (a page closed mid-request).
    for _ in 0..16 {
        let body = serde_json::json!({ "document": "d1", "scene": { "handles": [[1, 1]] } });
        let request = send(addr, "POST", "/api/rig", body.to_string().into_bytes());
        let _ = tokio::time::timeout(Duration::from_millis(1), request).await;
    }
    // Bodies at the limit (a 4xx naming what is wrong: not an SVG) and over it (413).
    let mut at_limit = b"<svg xmlns=\"http://www.w3.org/2000/svg\"><!-- ".to_vec();
    at_limit.resize(MAX_UPLOAD_BYTES, b'x');
    let t = Instant::now();
    let answer = send(addr, "POST", "/api/open", at_limit).await;
    tally.record("open at the limit", t, &answer);
    let over = vec![b' '; MAX_UPLOAD_BYTES + 1];
    let t = Instant::now();
    let answer = send(addr, "POST", "/api/open", over).await;
    assert_eq!(answer.as_ref().map(|a| a.status).ok(), Some(413));
    tally.record("open over the limit", t, &answer);
    // Garbage to every kind of route.
    for (k, target) in [
        "/api/rig",
        "/api/rigs/r1/solve",
        "/api/documents/d1/export?viewbox=keep",
        "/api/documents/d1/lottie",
        "/api/defop",
        "/api/subdiv/open",
        "/api/weights/columns",
    ]
    .into_iter()
    .enumerate()
    {
        let garbage: Vec<u8> = (0..997).map(|i| ((i * 31 + k * 7) % 251) as u8).collect();
        let t = Instant::now();
        let answer = send(addr, "POST", target, garbage).await;
        tally.record("garbage", t, &answer);
    }
    slow.join().unwrap();
    tally
}

/// The tallies of `clients`, merged.
async fn merged(clients: Vec<tokio::task::JoinHandle<Tally>>) -> Tally {
    let mut all = Tally::default();
    for c in clients {
        all.merge(c.await.unwrap());
    }
    all
}

/// The report's line of a phase: what ran, its seconds since `started`, and the server's peak
/// memory so far.
fn phase_line(what: &str, started: Instant, server: &Server) -> String {
    format!(
        "{what} in {:.1} s; peak memory {:.0} MiB\n",
        started.elapsed().as_secs_f64(),
        server.peak_memory() as f64 / (1 << 20) as f64
    )
}

/// The `q`-quantile of `values` (sorted in place), nearest rank.
fn quantile(values: &mut [f64], q: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    let i = ((q * values.len() as f64).ceil() as usize).clamp(1, values.len()) - 1;
    values[i]
}

#[test]
fn serve_under_load_and_faults() {
    let server = Server::start();
    let addr = server.addr;
    let started = Instant::now();
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    let local = tokio::task::LocalSet::new();
    let mut tally = local.block_on(&runtime, async move {
        let clients: Vec<_> = (0..CLIENTS)
            .map(|k| tokio::task::spawn_local(client(addr, k, false)))
            .collect();
        let mut all = faults(addr).await;
        all.merge(merged(clients).await);
        // Still serving, every slot back: a request of each kind answers.
        let initial = send(addr, "GET", "/api/initial", Vec::new()).await;
        all.record("initial after", Instant::now(), &initial);
        assert_eq!(initial.map(|a| a.status).ok(), Some(200));
        all
    });
    let what = format!("serve under load: {CLIENTS} clients × {ROUNDS} rounds");
    let mut report = phase_line(&what, started, &server);
    report.push_str(&table(&mut tally));
    // Within the store's limits (as many editors as it keeps rigs, each opening and rigging
    // once, then posing, asking weights and exporting), every request succeeds: the
    // latencies of the work itself.
    let started = Instant::now();
    let mut within = local.block_on(&runtime, async move {
        let clients: Vec<_> = (0..MAX_RIGS)
            .map(|k| tokio::task::spawn_local(client(addr, k, true)))
            .collect();
        // A job slot left taken by an abandoned request would hold these up: bounded.
        let joined = tokio::time::timeout(Duration::from_secs(120), merged(clients));
        joined.await.expect("the clients within the limits finish")
    });
    let what = format!(
        "within the store's limits: {MAX_RIGS} clients, each one document and one rig, × {ROUNDS} rounds"
    );
    report.push_str(&phase_line(&what, started, &server));
    report.push_str(&table(&mut within));
    // The heavy routes, more editors than job slots, then jobs abandoned mid-run.
    let started = Instant::now();
    let mut heavy = local.block_on(&runtime, async move {
        let clients: Vec<_> = (0..HEAVY_CLIENTS)
            .map(|k| tokio::task::spawn_local(heavy_client(addr, k)))
            .collect();
        let mut all = merged(clients).await;
        all.merge(abandoned_jobs(addr).await);
        all
    });
    let what = format!(
        "heavy routes: {HEAVY_CLIENTS} clients × {HEAVY_ROUNDS} rounds, then {ABANDONED} rigs abandoned mid-job"
    );
    report.push_str(&phase_line(&what, started, &server));
    report.push_str(&table(&mut heavy));
    eprint!("{report}");
    let _ = std::io::stderr().flush();
    assert!(heavy.wrong.is_empty(), "{}", heavy.wrong.join("\n"));
    for route in ["rig (bbw)", "refine", "defop", "lottie", "subdiv rig"] {
        let ok = heavy.statuses.get(&(route, 200)).copied().unwrap_or(0);
        assert!(ok > 0, "no {route} succeeded:\n{report}");
    }
    assert!(within.wrong.is_empty(), "{}", within.wrong.join("\n"));
    for ((route, status), n) in &within.statuses {
        assert_eq!(*status, 200, "{n} × {route}: {status}\n{report}");
    }
    assert!(tally.wrong.is_empty(), "{}", tally.wrong.join("\n"));
    for route in ["open", "rig", "solve", "weights", "export"] {
        let ok = tally.statuses.get(&(route, 200)).copied().unwrap_or(0);
        assert!(ok > 0, "no {route} succeeded:\n{report}");
    }
    assert_eq!(
        tally.latencies["open"].len(),
        CLIENTS * ROUNDS,
        "every open answered"
    );
    let mut server = server;
    assert!(
        server.child.try_wait().unwrap().is_none(),
        "the server exited"
    );
    assert!(server.peak_memory() < PEAK_MEMORY, "{report}");
}
