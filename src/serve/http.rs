//! The HTTP side: the embedded page, a small JSON API and the WebSocket streams (axum on
//! tokio).
//!
//! Routes:
//! - `GET /` (the page; its settings come from the query, e.g. `/?preset=fig5&n=8&autoplay=1`),
//!   `GET /app.js`, `GET /style.css`: embedded in the binary.
//! - `GET /api/presets`: the presets (name, title, scenario TOML) as JSON.
//! - `GET /api/check?...` and `POST /api/check` (a JSON object of settings): `200` with the
//!   settings as a scenario, or `400` with `{"error": ...}` naming the parameter.
//! - `GET /api/stats`: open sessions and the limit.
//! - `GET /api/roughness?n=N`: the roughness exponent alpha of the flat-substrate rule
//!   (`n` 0 to 8, default 0) from the saturated widths of `L` = 16, 32, 64 (4 seeds each;
//!   about a second).
//! - `GET /ws/growth?...`, `GET /ws/ripple?...`: a session per connection (settings checked
//!   before the upgrade: `400` on bad settings, `503` when full). The client sends JSON
//!   commands (`{"cmd": "play" | "pause" | "step" | "explain" | "reset" | "scenario"}`,
//!   `{"cmd": "speed", "value": N}`, ripple: `{"cmd": "current", "speed": S, "angle": A}`);
//!   the server sends a binary frame ([`GrowthSession::encode`], [`RippleSession::encode`])
//!   and a JSON `stats` message per frame, `pick` messages in explain mode, and `error`
//!   messages for bad commands (the session goes on). A closed socket ends its session.
//!
//! A paused session waits on its socket only (no timer runs); a playing one runs a frame per
//! tick of [`ServerConfig::frame_interval`] on the blocking pool.

use std::collections::BTreeMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use axum::Router;
use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::extract::{Query, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use serde_json::{Value, json};

use super::ServeError;
use super::session::{GrowthSession, RippleSession};
use super::settings::{GrowthSettings, PRESETS, RippleSettings};

const INDEX_HTML: &str = include_str!("page/index.html");
const APP_JS: &str = include_str!("page/app.js");
const STYLE_CSS: &str = include_str!("page/style.css");

/// The server's limits.
#[derive(Clone, Debug)]
pub struct ServerConfig {
    /// Most sessions held at once; more are refused with `503`. Default 64.
    pub max_sessions: usize,
    /// Time between frames of a playing session; default 25 ms (at most 40 frames/s).
    pub frame_interval: Duration,
}

impl Default for ServerConfig {
    fn default() -> Self {
        ServerConfig {
            max_sessions: 64,
            frame_interval: Duration::from_millis(25),
        }
    }
}

struct AppState {
    config: ServerConfig,
    sessions: AtomicUsize,
}

/// Holds one session slot; frees it when dropped (the socket closed).
struct Slot(Arc<AppState>);

impl Slot {
    fn take(state: &Arc<AppState>) -> Result<Slot, ServeError> {
        let max = state.config.max_sessions;
        state
            .sessions
            .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |n| {
                (n < max).then_some(n + 1)
            })
            .map_err(|_| ServeError::Busy(max))?;
        Ok(Slot(state.clone()))
    }
}

impl Drop for Slot {
    fn drop(&mut self) {
        self.0.sessions.fetch_sub(1, Ordering::SeqCst);
    }
}

fn error_response(e: &ServeError) -> Response {
    let status = match e {
        ServeError::Busy(_) => StatusCode::SERVICE_UNAVAILABLE,
        _ => StatusCode::BAD_REQUEST,
    };
    (status, axum::Json(json!({ "error": e.to_string() }))).into_response()
}

/// The application: every route, with the given limits.
pub fn router(config: ServerConfig) -> Router {
    let state = Arc::new(AppState {
        config,
        sessions: AtomicUsize::new(0),
    });
    Router::new()
        .route("/", get(index))
        .route("/index.html", get(index))
        .route("/app.js", get(app_js))
        .route("/style.css", get(style_css))
        .route("/api/presets", get(presets))
        .route("/api/check", get(check_get).post(check_post))
        .route("/api/stats", get(stats))
        .route("/api/roughness", get(roughness))
        .route("/ws/growth", get(ws_growth))
        .route("/ws/ripple", get(ws_ripple))
        .fallback(not_found)
        .with_state(state)
}

/// Serves the application on `listener` until the process ends.
pub async fn serve(listener: tokio::net::TcpListener, config: ServerConfig) -> std::io::Result<()> {
    axum::serve(listener, router(config)).await
}

async fn index() -> impl IntoResponse {
    (
        [(header::CONTENT_TYPE, "text/html; charset=utf-8")],
        INDEX_HTML,
    )
}
async fn app_js() -> impl IntoResponse {
    (
        [(header::CONTENT_TYPE, "text/javascript; charset=utf-8")],
        APP_JS,
    )
}
async fn style_css() -> impl IntoResponse {
    (
        [(header::CONTENT_TYPE, "text/css; charset=utf-8")],
        STYLE_CSS,
    )
}
async fn not_found() -> Response {
    (
        StatusCode::NOT_FOUND,
        axum::Json(json!({ "error": "no such page: see / or /api/presets" })),
    )
        .into_response()
}

async fn presets() -> impl IntoResponse {
    let list: Vec<Value> = PRESETS
        .iter()
        .map(|(n, t, toml)| json!({ "name": n, "title": t, "toml": toml }))
        .collect();
    axum::Json(Value::Array(list))
}

async fn stats(State(s): State<Arc<AppState>>) -> impl IntoResponse {
    axum::Json(json!({
        "sessions": s.sessions.load(Ordering::SeqCst),
        "max_sessions": s.config.max_sessions,
    }))
}

async fn roughness(Query(q): Query<BTreeMap<String, String>>) -> Response {
    use crate::engine::lattice::Neighbourhood;
    use crate::growth::roughness::{RoughnessRun, roughness_exponent};
    if let Some(k) = q.keys().find(|k| k.as_str() != "n") {
        return error_response(&ServeError::UnknownParameter {
            parameter: k.clone(),
            known: "n".into(),
        });
    }
    let n = match q.get("n").map(|v| v.trim().parse::<f64>()) {
        None => 0.0,
        Some(Ok(n)) if (0.0..=8.0).contains(&n) => n,
        Some(_) => {
            return error_response(&ServeError::Parameter {
                parameter: "n".into(),
                value: q["n"].clone(),
                expected: "a number from 0 to 8".into(),
            });
        }
    };
    let base = RoughnessRun {
        lattice: Neighbourhood::Hex,
        width: 16,
        n,
        monolayers: 1.0,
        seed: 1,
    };
    let r =
        tokio::task::spawn_blocking(move || roughness_exponent(&base, &[16, 32, 64], 8.0, 4)).await;
    match r {
        Ok(Ok((alpha, pts))) => axum::Json(json!({
            "n": n,
            "alpha": alpha,
            "points": pts.iter().map(|&(l, w, se)| json!({"width": l, "w_sat": w, "se": se}))
                .collect::<Vec<_>>(),
        }))
        .into_response(),
        Ok(Err(e)) => error_response(&ServeError::Scene(e.to_string())),
        Err(_) => (StatusCode::INTERNAL_SERVER_ERROR, "roughness run failed").into_response(),
    }
}

fn check(q: &BTreeMap<String, String>) -> Response {
    match GrowthSettings::from_query(q) {
        Ok(s) => axum::Json(json!({
            "ok": true,
            "preset": s.preset,
            "cells": s.scene.width * s.scene.height,
            "speed": s.speed,
            "scenario": s.scenario_toml(1.0),
        }))
        .into_response(),
        Err(e) => error_response(&e),
    }
}

async fn check_get(Query(q): Query<BTreeMap<String, String>>) -> Response {
    check(&q)
}

/// A JSON object of settings: values may be strings, numbers or booleans.
fn json_settings(body: &str) -> Result<BTreeMap<String, String>, ServeError> {
    let v: Value = serde_json::from_str(body).map_err(|e| ServeError::Json(e.to_string()))?;
    let Value::Object(map) = v else {
        return Err(ServeError::Json(
            "expected an object of settings, e.g. {\"preset\": \"fig5\", \"n\": 8}".into(),
        ));
    };
    map.into_iter()
        .map(|(k, v)| match v {
            Value::String(s) => Ok((k, s)),
            Value::Number(n) => Ok((k, n.to_string())),
            Value::Bool(b) => Ok((k, (b as u8).to_string())),
            other => Err(ServeError::Parameter {
                parameter: k,
                value: other.to_string(),
                expected: "a string, number or boolean".into(),
            }),
        })
        .collect()
}

async fn check_post(body: String) -> Response {
    match json_settings(&body) {
        Ok(q) => check(&q),
        Err(e) => error_response(&e),
    }
}

async fn ws_growth(
    State(state): State<Arc<AppState>>,
    Query(q): Query<BTreeMap<String, String>>,
    ws: WebSocketUpgrade,
) -> Response {
    let live = GrowthSettings::from_query(&q)
        .and_then(GrowthSession::new)
        .map(|s| Live::Growth(Box::new(s)));
    upgrade(&state, live, ws)
}

async fn ws_ripple(
    State(state): State<Arc<AppState>>,
    Query(q): Query<BTreeMap<String, String>>,
    ws: WebSocketUpgrade,
) -> Response {
    let live = RippleSettings::from_query(&q)
        .and_then(RippleSession::new)
        .map(|s| Live::Ripple(Box::new(s)));
    upgrade(&state, live, ws)
}

/// Starts a session built from the request (or answers its error), if a slot is free.
fn upgrade(
    state: &Arc<AppState>,
    live: Result<Live, ServeError>,
    ws: WebSocketUpgrade,
) -> Response {
    let live = match live {
        Ok(l) => l,
        Err(e) => return error_response(&e),
    };
    let slot = match Slot::take(state) {
        Ok(s) => s,
        Err(e) => return error_response(&e),
    };
    let interval = state.config.frame_interval;
    ws.on_upgrade(move |socket| run_session(socket, live, interval, slot))
}

/// A live session of either kind.
enum Live {
    Growth(Box<GrowthSession>),
    Ripple(Box<RippleSession>),
}

impl Live {
    fn frame(&mut self) -> u64 {
        match self {
            Live::Growth(s) => s.frame(),
            Live::Ripple(s) => s.frame(),
        }
    }
    fn encode(&self, buf: &mut Vec<u8>) {
        match self {
            Live::Growth(s) => s.encode(buf),
            Live::Ripple(s) => s.encode(buf),
        }
    }
    fn stats(&self) -> Value {
        match self {
            Live::Growth(s) => serde_json::to_value(s.stats()).unwrap_or(Value::Null),
            Live::Ripple(s) => serde_json::to_value(s.stats()).unwrap_or(Value::Null),
        }
    }
    fn info(&self) -> Value {
        match self {
            Live::Growth(s) => {
                let mut v = controls(s.settings());
                // The preset's own values, so that the page's links name only what differs.
                let name = s.settings().preset.split('+').next().unwrap_or("fig5");
                let q = BTreeMap::from([("preset".to_string(), name.to_string())]);
                let defaults = GrowthSettings::from_query(&q)
                    .map(|d| controls(&d))
                    .unwrap_or(Value::Null);
                if let Value::Object(m) = &mut v {
                    m.insert("type".into(), "info".into());
                    m.insert("model".into(), "growth".into());
                    m.insert("preset".into(), s.settings().preset.clone().into());
                    m.insert("scene".into(), s.settings().scene.scene.name().into());
                    m.insert("defaults".into(), defaults);
                }
                v
            }
            Live::Ripple(_) => json!({ "type": "info", "model": "ripple" }),
        }
    }
}

/// The page's controls of a growth session, by their URL names.
fn controls(s: &GrowthSettings) -> Value {
    let c = &s.scene;
    let rule: Vec<String> = c.ca_rule.iter().map(|b| b.to_string()).collect();
    json!({
        "lattice": c.lattice.name(), "width": c.width, "height": c.height,
        "boundary": c.boundary.name(), "n": c.n, "weight": c.weight, "shape": c.shape.name(),
        "start": c.start, "sampler": c.sampler.name(), "seed": c.seed, "speed": s.speed,
        "ca_rule": rule.join(","),
    })
}

/// What the frame loop sends after a frame.
struct Frame {
    binary: Vec<u8>,
    stats: Value,
    events: u64,
    compute_ms: f64,
}

/// Runs a frame (or none, for a fresh or reset session) on the blocking pool.
async fn compute(mut live: Live, run: bool) -> (Live, Frame) {
    let joined = tokio::task::spawn_blocking(move || {
        let t0 = Instant::now();
        let events = if run { live.frame() } else { 0 };
        let mut buf = Vec::new();
        live.encode(&mut buf);
        let stats = live.stats();
        let compute_ms = t0.elapsed().as_secs_f64() * 1e3;
        (
            live,
            Frame {
                binary: buf,
                stats,
                events,
                compute_ms,
            },
        )
    })
    .await;
    match joined {
        Ok(x) => x,
        // A panic in a frame is a bug; it ends this session only.
        Err(e) => std::panic::resume_unwind(e.into_panic()),
    }
}

async fn send_json(socket: &mut WebSocket, v: Value) -> bool {
    socket
        .send(Message::Text(v.to_string().into()))
        .await
        .is_ok()
}

async fn send_frame(socket: &mut WebSocket, f: Frame, playing: bool, fps: f64) -> bool {
    if socket.send(Message::Binary(f.binary.into())).await.is_err() {
        return false;
    }
    let mut stats = f.stats;
    if let Value::Object(m) = &mut stats {
        m.insert("type".into(), "stats".into());
        m.insert("playing".into(), playing.into());
        m.insert("fps".into(), fps.into());
        m.insert("frame_ms".into(), f.compute_ms.into());
        m.insert("events".into(), f.events.into());
    }
    send_json(socket, stats).await
}

async fn run_session(mut socket: WebSocket, live: Live, interval: Duration, _slot: Slot) {
    if !send_json(&mut socket, live.info()).await {
        return;
    }
    let (mut live, frame) = compute(live, false).await;
    if !send_frame(&mut socket, frame, false, 0.0).await {
        return;
    }
    let mut playing = false;
    let mut ticker = tokio::time::interval(interval);
    ticker.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
    // Frames sent in the current one-second window, and the last window's rate.
    let (mut window_start, mut window_frames, mut fps) = (Instant::now(), 0u32, 0.0);
    loop {
        let mut run_frame = false;
        tokio::select! {
            msg = socket.recv() => {
                let text = match msg {
                    None | Some(Err(_)) | Some(Ok(Message::Close(_))) => break,
                    Some(Ok(Message::Text(t))) => t.to_string(),
                    Some(Ok(_)) => continue,
                };
                match command(&mut live, &text) {
                    Ok(Cmd::Play) => {
                        playing = true;
                        ticker.reset();
                        window_start = Instant::now();
                        window_frames = 0;
                    }
                    Ok(Cmd::Pause) => {
                        playing = false;
                        let (l, f) = compute(live, false).await;
                        live = l;
                        if !send_frame(&mut socket, f, playing, fps).await { break; }
                    }
                    Ok(Cmd::Step) => {
                        playing = false;
                        run_frame = true;
                    }
                    Ok(Cmd::Redraw) => {
                        let (l, f) = compute(live, false).await;
                        live = l;
                        if !send_frame(&mut socket, f, playing, fps).await { break; }
                    }
                    Ok(Cmd::Reply(v)) => {
                        if !send_json(&mut socket, v).await { break; }
                    }
                    Ok(Cmd::Explain) => {
                        playing = false;
                        let v = match &mut live {
                            Live::Growth(s) => match s.explain() {
                                Some(e) => json!({ "type": "pick", "explained": e }),
                                None => json!({ "type": "error", "message": "the run cannot go on: reset it" }),
                            },
                            Live::Ripple(_) => json!({ "type": "error", "message": "explain mode is for the growth model" }),
                        };
                        let (l, f) = compute(live, false).await;
                        live = l;
                        if !send_frame(&mut socket, f, playing, fps).await { break; }
                        if !send_json(&mut socket, v).await { break; }
                    }
                    Err(e) => {
                        if !send_json(&mut socket, json!({ "type": "error", "message": e.to_string() })).await { break; }
                    }
                }
            }
            _ = ticker.tick(), if playing => { run_frame = true; }
        }
        if run_frame {
            let (l, f) = compute(live, true).await;
            live = l;
            window_frames += 1;
            let el = window_start.elapsed().as_secs_f64();
            if el >= 1.0 {
                fps = window_frames as f64 / el;
                window_start = Instant::now();
                window_frames = 0;
            }
            if !send_frame(&mut socket, f, playing, fps).await {
                break;
            }
        }
    }
}

/// A parsed client command.
enum Cmd {
    Play,
    Pause,
    Step,
    Explain,
    /// The state changed without a frame (reset, speed, current): send it.
    Redraw,
    /// Answer with this message.
    Reply(Value),
}

/// Reads a client command and applies what needs no frame.
fn command(live: &mut Live, text: &str) -> Result<Cmd, ServeError> {
    let v: Value = serde_json::from_str(text).map_err(|e| ServeError::Json(e.to_string()))?;
    let name = v
        .get("cmd")
        .and_then(Value::as_str)
        .ok_or_else(|| ServeError::Json("expected {\"cmd\": \"play\" | \"pause\" | ...}".into()))?;
    let number = |key: &str, lo: f64, hi: f64| -> Result<f64, ServeError> {
        match v.get(key).and_then(Value::as_f64) {
            Some(x) if x.is_finite() && x >= lo && x <= hi => Ok(x),
            _ => Err(ServeError::Parameter {
                parameter: key.to_string(),
                value: v.get(key).map_or("missing".into(), Value::to_string),
                expected: format!("a number from {lo} to {hi}"),
            }),
        }
    };
    Ok(match name {
        "play" => Cmd::Play,
        "pause" => Cmd::Pause,
        "step" => Cmd::Step,
        "explain" => Cmd::Explain,
        "reset" => {
            match live {
                Live::Growth(s) => s.reset()?,
                Live::Ripple(s) => s.reset()?,
            }
            Cmd::Redraw
        }
        "speed" => {
            // a whole number of events (growth) or steps (ripple) per frame: a fraction is
            // refused, never truncated
            let whole = |hi: f64| -> Result<u64, ServeError> {
                let x = number("value", 1.0, hi)?;
                if x.fract() != 0.0 {
                    return Err(ServeError::Parameter {
                        parameter: "value".into(),
                        value: x.to_string(),
                        expected: format!("a whole number from 1 to {hi}"),
                    });
                }
                Ok(x as u64)
            };
            match live {
                Live::Growth(s) => s.set_speed(whole(1e5)?),
                Live::Ripple(s) => s.set_speed(whole(200.0)?),
            }
            Cmd::Redraw
        }
        "current" => match live {
            Live::Ripple(s) => {
                s.set_current(number("speed", 0.0, 10.0)?, number("angle", -360.0, 360.0)?)?;
                Cmd::Redraw
            }
            Live::Growth(_) => {
                return Err(ServeError::Parameter {
                    parameter: "cmd".into(),
                    value: "current".into(),
                    expected: "a ripple-session command (this is a growth session)".into(),
                });
            }
        },
        "scenario" => match live {
            Live::Growth(s) => Cmd::Reply(json!({
                "type": "scenario",
                "toml": s.settings().scenario_toml(s.growth().time()),
            })),
            Live::Ripple(_) => Cmd::Reply(json!({
                "type": "error", "message": "scenario export is for the growth model",
            })),
        },
        other => {
            return Err(ServeError::Parameter {
                parameter: "cmd".into(),
                value: other.to_string(),
                expected: "play, pause, step, explain, reset, speed, current or scenario".into(),
            });
        }
    })
}
