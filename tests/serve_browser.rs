//! The page in a real browser: Debian's headless Chromium, driven over the DevTools protocol.
//!
//! Starts `cellsurf serve --port 0`, opens the page, presses Play, waits, and checks that the
//! live counters `#steps`, `#accepted` and `#occupied` advanced and that a screenshot of the
//! page is not blank. Chromium is required: `.ci/run` installs it when missing; the test fails
//! without it unless `CELLSURF_SKIP_BROWSER=1` is set. With `CELLSURF_SCREENSHOTS=DIR` the
//! screenshots are written there (that is how `docs/serve*.png` were made).

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use futures_util::{SinkExt, StreamExt};
use serde_json::{Value, json};
use tokio_tungstenite::tungstenite::Message;

struct Kill(Child);
impl Drop for Kill {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn start_server() -> (Kill, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_cellsurf"))
        .args(["serve", "--port", "0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start cellsurf serve");
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let url = line
        .split_whitespace()
        .find(|w| w.starts_with("http://"))
        .unwrap_or_else(|| panic!("no address in {line:?}"))
        .to_string();
    (Kill(child), url)
}

fn chromium() -> Option<String> {
    for name in ["chromium", "chromium-browser", "google-chrome"] {
        let ok = Command::new("sh")
            .args(["-c", &format!("command -v {name}")])
            .output()
            .is_ok_and(|o| o.status.success());
        if ok {
            return Some(name.to_string());
        }
    }
    None
}

fn start_chromium(bin: &str, profile: &std::path::Path) -> (Kill, String) {
    let mut child = Kill(
        Command::new(bin)
            .args([
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--hide-scrollbars",
                "--no-first-run",
                "--remote-debugging-port=0",
                "--window-size=1400,1250",
            ])
            .arg(format!("--user-data-dir={}", profile.display()))
            .arg("about:blank")
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start chromium"),
    );
    let err = BufReader::new(child.0.stderr.take().unwrap());
    let t0 = Instant::now();
    for line in err.lines() {
        let line = line.unwrap_or_default();
        if let Some(i) = line.find("ws://") {
            let ws = line[i..].trim().to_string();
            let port = ws
                .trim_start_matches("ws://")
                .split('/')
                .next()
                .unwrap()
                .to_string();
            return (child, port);
        }
        assert!(
            t0.elapsed() < Duration::from_secs(30),
            "chromium did not start"
        );
    }
    panic!("chromium exited without a DevTools address");
}

/// A DevTools session on one page.
struct Cdp {
    ws: tokio_tungstenite::WebSocketStream<
        tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>,
    >,
    id: u64,
}

impl Cdp {
    async fn call(&mut self, method: &str, params: Value) -> Value {
        self.id += 1;
        let id = self.id;
        let msg = json!({ "id": id, "method": method, "params": params }).to_string();
        self.ws.send(Message::Text(msg.into())).await.unwrap();
        loop {
            let m = tokio::time::timeout(Duration::from_secs(30), self.ws.next())
                .await
                .expect("DevTools answer")
                .unwrap()
                .unwrap();
            if let Message::Text(t) = m {
                let v: Value = serde_json::from_str(&t).unwrap();
                if v["id"] == id {
                    assert!(v.get("error").is_none(), "{method}: {v}");
                    return v["result"].clone();
                }
            }
        }
    }
    async fn eval(&mut self, expr: &str) -> Value {
        let r = self
            .call(
                "Runtime.evaluate",
                json!({ "expression": expr, "returnByValue": true }),
            )
            .await;
        assert!(r.get("exceptionDetails").is_none(), "{expr}: {r}");
        r["result"]["value"].clone()
    }
    async fn counters(&mut self) -> (f64, f64, f64) {
        let v = self
            .eval(
                "JSON.stringify(['steps','accepted','occupied'].map(i => document.getElementById(i).textContent))",
            )
            .await;
        let a: Vec<String> = serde_json::from_str(v.as_str().unwrap()).unwrap();
        let p = |s: &str| s.parse::<f64>().unwrap_or(f64::NAN);
        (p(&a[0]), p(&a[1]), p(&a[2]))
    }
    async fn wait_for(&mut self, expr: &str, secs: u64) {
        let t0 = Instant::now();
        let guarded =
            format!("(() => {{ try {{ return {expr}; }} catch (e) {{ return false; }} }})()");
        while self.eval(&guarded).await != Value::Bool(true) {
            assert!(
                t0.elapsed() < Duration::from_secs(secs),
                "timed out waiting for {expr}"
            );
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    }
    async fn screenshot(&mut self) -> Vec<u8> {
        let r = self
            .call("Page.captureScreenshot", json!({ "format": "png" }))
            .await;
        base64(r["data"].as_str().unwrap())
    }
}

fn base64(s: &str) -> Vec<u8> {
    let val = |c: u8| -> u32 {
        match c {
            b'A'..=b'Z' => (c - b'A') as u32,
            b'a'..=b'z' => (c - b'a' + 26) as u32,
            b'0'..=b'9' => (c - b'0' + 52) as u32,
            b'+' => 62,
            b'/' => 63,
            _ => 0,
        }
    };
    let b: Vec<u8> = s.bytes().filter(|c| !c.is_ascii_whitespace()).collect();
    let mut out = Vec::with_capacity(b.len() * 3 / 4);
    for chunk in b.chunks(4) {
        let pad = chunk.iter().filter(|&&c| c == b'=').count();
        let n = chunk.iter().fold(0u32, |a, &c| (a << 6) | val(c)) << (6 * (4 - chunk.len()));
        let bytes = [(n >> 16) as u8, (n >> 8) as u8, n as u8];
        out.extend_from_slice(&bytes[..3 - pad.min(2)]);
    }
    out
}

/// Distinct colours in a PNG (RGB or RGBA, 8 bit) and its size.
fn colours(png_bytes: &[u8]) -> (usize, u32, u32) {
    let dec = png::Decoder::new(std::io::Cursor::new(png_bytes));
    let mut r = dec.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    let ch = info.color_type.samples();
    let mut set = std::collections::HashSet::new();
    for px in buf[..info.buffer_size()].chunks(ch).step_by(7) {
        set.insert((px[0], px[1], px[2]));
        if set.len() > 1000 {
            break;
        }
    }
    (set.len(), info.width, info.height)
}

#[test]
fn page_plays_in_headless_chromium() {
    let Some(bin) = chromium() else {
        if std::env::var("CELLSURF_SKIP_BROWSER").as_deref() == Ok("1") {
            eprintln!("SKIPPED: no chromium found and CELLSURF_SKIP_BROWSER=1");
            return;
        }
        panic!(
            "the browser test needs Debian's chromium (apt-get install chromium; .ci/run installs it); set CELLSURF_SKIP_BROWSER=1 to skip it"
        );
    };
    let (_server, url) = start_server();
    let profile = std::env::temp_dir().join(format!("cellsurf-chromium-{}", std::process::id()));
    let (_browser, port) = start_chromium(&bin, &profile);
    let text = ureq::get(&format!("http://{port}/json/list"))
        .call()
        .unwrap()
        .body_mut()
        .read_to_string()
        .unwrap();
    let list: Value = serde_json::from_str(&text).unwrap();
    let target = list
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["type"] == "page")
        .expect("a page target")["webSocketDebuggerUrl"]
        .as_str()
        .unwrap()
        .to_string();
    let shots = std::env::var("CELLSURF_SCREENSHOTS").ok();
    let rt = tokio::runtime::Runtime::new().unwrap();
    rt.block_on(async {
        let (ws, _) = tokio_tungstenite::connect_async(target.as_str()).await.unwrap();
        let mut cdp = Cdp { ws, id: 0 };
        cdp.call("Page.enable", json!({})).await;
        cdp.call("Page.navigate", json!({ "url": format!("{url}?preset=fig5&speed=100") }))
            .await;
        cdp.wait_for(
            "document.getElementById('status') && document.getElementById('status').textContent === 'paused'",
            20,
        )
        .await;
        let c0 = cdp.counters().await;
        cdp.eval("document.getElementById('play').click(); true").await;
        tokio::time::sleep(Duration::from_millis(2500)).await;
        cdp.eval("document.getElementById('play').click(); true").await;
        tokio::time::sleep(Duration::from_millis(300)).await;
        let c1 = cdp.counters().await;
        assert!(c1.0 > c0.0, "#steps did not advance: {c0:?} -> {c1:?}");
        assert!(c1.1 > c0.1, "#accepted did not advance: {c0:?} -> {c1:?}");
        assert!(c1.2 > c0.2, "#occupied did not advance: {c0:?} -> {c1:?}");
        let png = cdp.screenshot().await;
        if let Some(dir) = &shots {
            std::fs::write(format!("{dir}/serve.png"), &png).unwrap();
        }
        let (n, w, h) = colours(&png);
        assert!(w > 800 && h > 600, "{w} x {h}");
        assert!(n > 20, "the screenshot is blank: {n} colours");
        // The lattice canvas itself holds occupied, surface and empty cells.
        let lattice = cdp
            .eval(
                "(() => { const c = document.getElementById('canvas'); const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data; const s = new Set(); for (let i = 0; i < d.length; i += 4 * 13) s.add(d[i] + ',' + d[i + 1] + ',' + d[i + 2]); return s.size; })()",
            )
            .await;
        assert!(lattice.as_u64().unwrap_or(0) >= 3, "lattice canvas: {lattice}");
        // "Copy link" gives the link of the current settings.
        let link = cdp
            .eval("document.getElementById('copylink').click(); document.getElementById('linktext').value")
            .await;
        let link = link.as_str().unwrap_or_default().to_string();
        assert!(link.contains("preset=fig5") && link.contains("speed=100"), "{link}");
        // Keyboard: Space plays, Space again pauses; S steps one frame.
        let key = |k: &str| {
            format!(
                "document.body.dispatchEvent(new KeyboardEvent('keydown', {{ key: '{k}', bubbles: true }})); true"
            )
        };
        cdp.eval(&key(" ")).await;
        cdp.wait_for("document.getElementById('status').textContent === 'playing'", 10)
            .await;
        cdp.eval(&key(" ")).await;
        cdp.wait_for("document.getElementById('status').textContent === 'paused'", 10)
            .await;
        tokio::time::sleep(Duration::from_millis(200)).await;
        let c2 = cdp.counters().await;
        cdp.eval(&key("s")).await;
        tokio::time::sleep(Duration::from_millis(500)).await;
        let c3 = cdp.counters().await;
        assert!(c3.1 > c2.1, "the S key did not step: {c2:?} -> {c3:?}");
        if let Some(dir) = &shots {
            // Explain mode on the rejection sampler, and the kinetic-roughening lesson.
            cdp.call("Page.navigate", json!({ "url": format!("{url}?preset=fig5&sampler=rejection&speed=40&autoplay=1") }))
                .await;
            cdp.wait_for("document.getElementById('status').textContent === 'playing'", 20).await;
            tokio::time::sleep(Duration::from_millis(1500)).await;
            cdp.eval("document.getElementById('play').click(); true").await;
            tokio::time::sleep(Duration::from_millis(300)).await;
            for _ in 0..3 {
                cdp.eval("document.getElementById('explain').click(); true").await;
                tokio::time::sleep(Duration::from_millis(200)).await;
            }
            std::fs::write(format!("{dir}/serve_explain.png"), cdp.screenshot().await).unwrap();
            cdp.call("Page.navigate", json!({ "url": format!("{url}?preset=kpz&speed=2048&autoplay=1") }))
                .await;
            cdp.wait_for("document.getElementById('status').textContent === 'playing'", 20).await;
            tokio::time::sleep(Duration::from_millis(4500)).await;
            cdp.eval("document.getElementById('alpha').click(); true").await;
            cdp.eval("document.getElementById('rplay').click(); true").await;
            tokio::time::sleep(Duration::from_millis(2500)).await;
            cdp.eval("window.scrollTo(0, 600); true").await;
            tokio::time::sleep(Duration::from_millis(200)).await;
            std::fs::write(format!("{dir}/serve_kpz.png"), cdp.screenshot().await).unwrap();
        }
    });
    let _ = std::fs::remove_dir_all(&profile);
}
