//! `cellsurf serve` over its HTTP and WebSocket API, on a loopback port chosen by the system:
//! presets, parameter errors (4xx naming the parameter; the server goes on), a bounded load
//! test of concurrent sessions, closed sessions freed, and the frame rate of a 256 x 256
//! hexagonal lattice at 10^4 events per frame.

use std::time::{Duration, Instant};

use cellsurf::serve::{GrowthSession, GrowthSettings, ServerConfig, serve};
use futures_util::{SinkExt, StreamExt};
use serde_json::{Value, json};
use tokio_tungstenite::tungstenite::Message;

type Ws =
    tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>;

async fn start() -> String {
    start_with(ServerConfig::default()).await
}

async fn start_with(config: ServerConfig) -> String {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    tokio::spawn(serve(listener, config));
    addr.to_string()
}

/// GET or POST on a blocking thread: (status, body).
async fn http(addr: &str, path: &str, post: Option<&str>) -> (u16, String) {
    let url = format!("http://{addr}{path}");
    let post = post.map(str::to_string);
    tokio::task::spawn_blocking(move || {
        let agent: ureq::Agent = ureq::Agent::config_builder()
            .http_status_as_error(false)
            .build()
            .into();
        let mut r = match post {
            None => agent.get(&url).call().unwrap(),
            Some(b) => agent.post(&url).send(b).unwrap(),
        };
        let status = r.status().as_u16();
        (status, r.body_mut().read_to_string().unwrap())
    })
    .await
    .unwrap()
}

async fn connect(addr: &str, path: &str) -> Ws {
    tokio_tungstenite::connect_async(format!("ws://{addr}{path}"))
        .await
        .unwrap()
        .0
}

async fn send(ws: &mut Ws, v: Value) {
    ws.send(Message::Text(v.to_string().into())).await.unwrap();
}

/// The next JSON message (skipping binary frames), within 10 s.
async fn next_json(ws: &mut Ws) -> Value {
    loop {
        let m = tokio::time::timeout(Duration::from_secs(10), ws.next())
            .await
            .expect("a message within 10 s")
            .unwrap()
            .unwrap();
        if let Message::Text(t) = m {
            return serde_json::from_str(&t).unwrap();
        }
    }
}

/// The next message of `kind` and the number of binary frames seen before it.
async fn next_of(ws: &mut Ws, kind: &str) -> (Value, usize) {
    let mut frames = 0;
    loop {
        let m = tokio::time::timeout(Duration::from_secs(10), ws.next())
            .await
            .expect("a message within 10 s")
            .unwrap()
            .unwrap();
        match m {
            Message::Binary(_) => frames += 1,
            Message::Text(t) => {
                let v: Value = serde_json::from_str(&t).unwrap();
                if v["type"] == kind {
                    return (v, frames);
                }
            }
            _ => {}
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn presets_stream_frames_and_grow() {
    let addr = start().await;
    let (status, body) = http(&addr, "/api/presets", None).await;
    assert_eq!(status, 200);
    let list: Value = serde_json::from_str(&body).unwrap();
    let names: Vec<&str> = list
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["fig3", "fig4", "fig5", "fig6", "fig7", "kpz"]);
    let (status, page) = http(&addr, "/?preset=fig5&n=8&autoplay=1", None).await;
    assert_eq!(status, 200);
    for id in [
        "id=\"steps\"",
        "id=\"accepted\"",
        "id=\"occupied\"",
        "/app.js",
    ] {
        assert!(page.contains(id), "page lacks {id}");
    }
    assert!(!page.contains("http://") || !page.contains("<script src=\"http"));
    for name in names {
        let mut ws = connect(&addr, &format!("/ws/growth?preset={name}&speed=50")).await;
        let info = next_json(&mut ws).await;
        assert_eq!(info["type"], "info");
        let (s0, frames) = next_of(&mut ws, "stats").await;
        assert_eq!(frames, 1, "{name}: a frame comes before its stats");
        assert_eq!(s0["time"], 0.0);
        send(&mut ws, json!({"cmd": "step"})).await;
        let (s1, _) = next_of(&mut ws, "stats").await;
        assert!(s1["accepted"].as_u64().unwrap() > 0, "{name}: {s1}");
        assert!(s1["occupied"].as_u64() > s0["occupied"].as_u64(), "{name}");
        // The scenario export reproduces the settings.
        send(&mut ws, json!({"cmd": "scenario"})).await;
        let (sc, _) = next_of(&mut ws, "scenario").await;
        let cfg =
            cellsurf::growth::scene::SceneConfig::from_toml(sc["toml"].as_str().unwrap()).unwrap();
        assert_eq!(
            cfg.steps as f64,
            s1["time"].as_f64().unwrap().max(1.0).ceil()
        );
    }
    // The n = 8 link of the issue.
    let mut ws = connect(&addr, "/ws/growth?preset=fig5&n=8&autoplay=1").await;
    let info = next_json(&mut ws).await;
    assert_eq!(info["n"], 8.0);
    assert_eq!(info["lattice"], "hex");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_requests_get_4xx_naming_the_parameter() {
    let addr = start().await;
    for (q, needle) in [
        ("n=-1", "n = -1"),
        ("n=20000", "n = 20000"),
        ("width=5000", "width = 5000"),
        ("width=1024&height=1024", "262144"),
        ("foo=1", "foo"),
        ("preset=fig9", "preset = fig9"),
        ("speed=0", "speed = 0"),
        ("sampler=gibbs", "sampler = gibbs"),
        ("shape=disc&start=1e6", "start"),
    ] {
        let (status, body) = http(&addr, &format!("/api/check?{q}"), None).await;
        assert_eq!(status, 400, "{q}: {body}");
        assert!(body.contains(needle), "{q}: {body}");
        // The WebSocket is refused before the upgrade, with the same message.
        let e = tokio_tungstenite::connect_async(format!("ws://{addr}/ws/growth?{q}"))
            .await
            .unwrap_err();
        assert!(e.to_string().contains("400"), "{q}: {e}");
    }
    let (status, body) = http(&addr, "/api/check", Some("{not json")).await;
    assert_eq!(status, 400);
    assert!(body.contains("malformed JSON"), "{body}");
    let (status, body) = http(&addr, "/api/check", Some("[1, 2]")).await;
    assert_eq!(status, 400, "{body}");
    let (status, body) = http(&addr, "/api/check", Some(r#"{"preset": "fig5", "n": -2}"#)).await;
    assert_eq!(status, 400);
    assert!(body.contains("n = -2"), "{body}");
    let (status, _) = http(&addr, "/api/check", Some(r#"{"preset": "fig7", "n": 3}"#)).await;
    assert_eq!(status, 200);
    let (status, body) = http(&addr, "/api/roughness?n=-1", None).await;
    assert_eq!(status, 400);
    assert!(body.contains("n = -1"), "{body}");
    let (status, _) = http(&addr, "/no/such/page", None).await;
    assert_eq!(status, 404);
    let e = tokio_tungstenite::connect_async(format!("ws://{addr}/ws/ripple?current_speed=50"))
        .await
        .unwrap_err();
    assert!(e.to_string().contains("400"), "{e}");
    // Bad commands on a live session: an error message, and the session goes on.
    let mut ws = connect(&addr, "/ws/growth?preset=fig5").await;
    next_of(&mut ws, "stats").await;
    for bad in [
        "{oops",
        r#"{"cmd": "fly"}"#,
        r#"{"cmd": "speed", "value": -5}"#,
        r#"{"cmd": "speed", "value": 1.9}"#,
        r#"{"x": 1}"#,
    ] {
        ws.send(Message::Text(bad.into())).await.unwrap();
        let (e, _) = next_of(&mut ws, "error").await;
        assert!(!e["message"].as_str().unwrap().is_empty(), "{bad}");
    }
    let (_, body) = http(&addr, "/api/check?speed=-5", None).await;
    assert!(body.contains("speed"), "{body}");
    let (_, body) = http(&addr, "/api/check?speed=1.9", None).await;
    assert!(
        body.contains("speed = 1.9"),
        "a fraction is refused, not truncated: {body}"
    );
    // a whole number written as a float is one (a JSON body's numbers arrive so)
    let (status, body) = http(&addr, "/api/check?speed=1e3&width=64.0", None).await;
    assert_eq!(status, 200, "{body}");
    send(&mut ws, json!({"cmd": "step"})).await;
    let (s, _) = next_of(&mut ws, "stats").await;
    assert!(s["accepted"].as_u64().unwrap() > 0);
    let (status, _) = http(&addr, "/api/stats", None).await;
    assert_eq!(status, 200, "the server is still up");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn twenty_sessions_play_at_once_and_closed_ones_are_freed() {
    let addr = start().await;
    const SESSIONS: usize = 20;
    let mut sockets = Vec::new();
    for k in 0..SESSIONS {
        let mut ws = connect(&addr, &format!("/ws/growth?preset=fig5&seed={k}&speed=200")).await;
        next_of(&mut ws, "stats").await;
        sockets.push(ws);
    }
    let (_, body) = http(&addr, "/api/stats", None).await;
    let st: Value = serde_json::from_str(&body).unwrap();
    assert_eq!(st["sessions"], SESSIONS);
    for ws in &mut sockets {
        send(ws, json!({"cmd": "play"})).await;
    }
    // Two seconds of play: every session keeps streaming.
    let t0 = Instant::now();
    let mut tasks = Vec::new();
    for mut ws in sockets {
        tasks.push(tokio::spawn(async move {
            let mut frames = 0;
            let mut last = Value::Null;
            while t0.elapsed() < Duration::from_secs(2) {
                let (s, f) = next_of(&mut ws, "stats").await;
                frames += f;
                last = s;
            }
            send(&mut ws, json!({"cmd": "pause"})).await;
            (ws, frames, last)
        }));
    }
    let mut sockets = Vec::new();
    let mut total = 0;
    for t in tasks {
        let (ws, frames, last) = tokio::time::timeout(Duration::from_secs(15), t)
            .await
            .expect("bounded")
            .unwrap();
        assert!(frames >= 10, "a session got only {frames} frames in 2 s");
        assert!(last["accepted"].as_u64().unwrap() > 1000, "{last}");
        total += frames;
        sockets.push(ws);
    }
    eprintln!(
        "{SESSIONS} sessions: {total} frames in 2 s ({:.1} frames/s each)",
        total as f64 / 2.0 / SESSIONS as f64
    );
    // Closing the sockets frees the sessions.
    for mut ws in sockets {
        ws.close(None).await.ok();
    }
    let t1 = Instant::now();
    loop {
        let (_, body) = http(&addr, "/api/stats", None).await;
        let st: Value = serde_json::from_str(&body).unwrap();
        if st["sessions"] == 0 {
            break;
        }
        assert!(
            t1.elapsed() < Duration::from_secs(5),
            "sessions not freed: {st}"
        );
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_paused_session_sends_nothing() {
    let addr = start().await;
    let mut ws = connect(&addr, "/ws/growth?preset=fig5").await;
    next_of(&mut ws, "stats").await;
    let quiet = tokio::time::timeout(Duration::from_millis(400), ws.next()).await;
    assert!(quiet.is_err(), "a paused session sent {quiet:?}");
    // The ripple section plays and takes the current.
    let mut r = connect(&addr, "/ws/ripple?speed=5").await;
    next_of(&mut r, "stats").await;
    send(
        &mut r,
        json!({"cmd": "current", "speed": 0.8, "angle": 180}),
    )
    .await;
    let (s, _) = next_of(&mut r, "stats").await;
    assert_eq!(s["current_speed"], 0.8);
    send(&mut r, json!({"cmd": "play"})).await;
    let (s, frames) = next_of(&mut r, "stats").await;
    assert!(frames == 1 && s["time"].as_u64().unwrap() >= 5, "{s}");
}

/// Frames per second of a session on a 256 x 256 hexagonal torus at 10^4 accepted events per
/// frame, with the frame encoded and the statistics measured (what the server does per
/// frame); the lattice is reset whenever it fills. Release builds must reach 30 frames/s.
#[test]
fn frame_rate_256_hex_at_1e4_events() {
    let q = [
        ("preset", "fig5"),
        ("width", "256"),
        ("height", "256"),
        ("speed", "10000"),
    ]
    .iter()
    .map(|(a, b)| (a.to_string(), b.to_string()))
    .collect();
    let mut s = GrowthSession::new(GrowthSettings::from_query(&q).unwrap()).unwrap();
    let mut buf = Vec::new();
    let t0 = Instant::now();
    let mut frames = 0;
    let mut events = 0;
    while t0.elapsed() < Duration::from_secs(1) {
        let e = s.frame();
        if e == 0 {
            s.reset().unwrap();
            continue;
        }
        events += e;
        s.encode(&mut buf);
        let st = s.stats();
        assert!(st.occupied > 0);
        frames += 1;
    }
    let fps = frames as f64 / t0.elapsed().as_secs_f64();
    eprintln!("256 x 256 hex, 1e4 events/frame: {fps:.0} frames/s ({events} events)");
    if !cfg!(debug_assertions) {
        assert!(fps >= 30.0, "{fps} frames/s");
    }
}

/// The same through the server: a playing session of a 256 x 256 hexagonal torus at 10^4
/// events per frame, frames counted at the client for two seconds (reset whenever the lattice
/// fills). The server sends at most 40 frames/s; release builds must deliver 30.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn server_streams_256_hex_at_30_frames_per_second() {
    let addr = start().await;
    let mut ws = connect(
        &addr,
        "/ws/growth?preset=fig5&width=256&height=256&speed=10000",
    )
    .await;
    next_of(&mut ws, "stats").await;
    send(&mut ws, json!({"cmd": "play"})).await;
    // Frames that ran events, and the time between consecutive ones (the gaps of a reset,
    // when the lattice has filled, left out).
    let t0 = Instant::now();
    let (mut running, mut active, mut events, mut server_fps) = (0u32, 0.0, 0u64, 0.0);
    let mut last: Option<Instant> = None;
    while t0.elapsed() < Duration::from_secs(2) {
        let (s, _) = next_of(&mut ws, "stats").await;
        let e = s["events"].as_u64().unwrap();
        server_fps = s["fps"].as_f64().unwrap();
        if e > 0 {
            let now = Instant::now();
            if let Some(prev) = last {
                running += 1;
                active += (now - prev).as_secs_f64();
            }
            last = Some(now);
            events += e;
        }
        if !s["stopped"].is_null() {
            last = None;
            send(&mut ws, json!({"cmd": "reset"})).await;
        }
    }
    let fps = running as f64 / active;
    eprintln!(
        "server, 256 x 256 hex, 1e4 events/frame: {fps:.1} frames/s at the client ({events} events in 2 s), server's own count {server_fps:.1}"
    );
    if !cfg!(debug_assertions) {
        assert!(fps >= 30.0, "{fps} frames/s");
    }
}

/// The exported scenario reproduces the session's lattice with `cellsurf grow --scenario`
/// (the library's `scene::run`), for each sampler, explained picks included.
#[test]
fn exported_scenario_reproduces_the_lattice() {
    use cellsurf::growth::scene::{NoHooks, SceneConfig, run};
    for (sampler, preset, speed) in [
        ("exact", "fig5", "300"),
        ("rejection", "fig7", "300"),
        ("ca", "fig4", "1"),
    ] {
        let q = [("preset", preset), ("sampler", sampler), ("speed", speed)]
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect();
        let mut s = GrowthSession::new(GrowthSettings::from_query(&q).unwrap()).unwrap();
        s.frame();
        for _ in 0..5 {
            s.explain().unwrap();
        }
        s.frame();
        let text = s.settings().scenario_toml(s.growth().time());
        let cfg = SceneConfig::from_toml(&text).unwrap();
        let r = run(&cfg, &mut NoHooks).unwrap();
        let snap = r.snapshots.last().unwrap();
        assert_eq!(snap.time, s.growth().time(), "{sampler}");
        assert_eq!(
            snap.states,
            s.growth().field_states(),
            "{sampler}: lattices differ"
        );
        assert_eq!(r.last.accepted, s.stats().accepted, "{sampler}");
    }
}

/// Above its session limit the server refuses a new session with 503 and a message, and takes
/// one again as soon as a tab closes.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn sessions_above_the_limit_are_refused() {
    let addr = start_with(ServerConfig {
        max_sessions: 2,
        ..ServerConfig::default()
    })
    .await;
    let mut a = connect(&addr, "/ws/growth?preset=fig3").await;
    let _b = connect(&addr, "/ws/ripple").await;
    next_of(&mut a, "stats").await;
    let e = tokio_tungstenite::connect_async(format!("ws://{addr}/ws/growth"))
        .await
        .unwrap_err();
    assert!(e.to_string().contains("503"), "{e}");
    a.close(None).await.unwrap();
    let t0 = Instant::now();
    loop {
        if tokio_tungstenite::connect_async(format!("ws://{addr}/ws/growth"))
            .await
            .is_ok()
        {
            break;
        }
        assert!(
            t0.elapsed() < Duration::from_secs(5),
            "the closed session was not freed"
        );
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}
