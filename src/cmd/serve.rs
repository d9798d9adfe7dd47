//! `cellsurf serve`: the interactive teaching page (see the library's `serve` module).

use std::io::Write;
use std::net::SocketAddr;

use anyhow::{Context, Result};
use clap::Parser;

use cellsurf::engine::count::CountRange;
use cellsurf::serve::{ServerConfig, serve};

/// Options of `cellsurf serve`.
#[derive(Parser, Debug)]
pub struct Args {
    /// Port to listen on (0: any free port; the address is printed on stdout).
    #[arg(long, default_value_t = 8080, value_parser = super::conv::parse_u16)]
    port: u16,
    /// Address to bind (an IP address, or localhost): loopback unless you mean to share the
    /// page on a network.
    #[arg(long, default_value = "127.0.0.1", value_parser = parse_host)]
    host: std::net::IpAddr,
    /// Open the page in the default browser (xdg-open / open / start).
    #[arg(long)]
    open: bool,
    /// Most sessions (open pages) held at once, 1 to 1024; more are refused.
    #[arg(long, default_value_t = 64, value_parser = parse_max_sessions)]
    max_sessions: u64,
}

/// `--max-sessions`: pages held at once.
const MAX_SESSIONS: CountRange = CountRange::new(1, 1024, "1 to 1024 sessions");

/// `--max-sessions`: a whole number (`1e2` accepted) in [`MAX_SESSIONS`].
fn parse_max_sessions(s: &str) -> Result<u64, String> {
    match super::conv::count_in::<u64>(MAX_SESSIONS)(s)? {
        v if MAX_SESSIONS.contains(v) => Ok(v),
        _ => Err(format!(
            "'{s}' is out of range: expected {}",
            MAX_SESSIONS.expected
        )),
    }
}

/// Runs the server until the process is stopped (Ctrl-C).
pub fn run(a: Args) -> Result<()> {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("cannot start the async runtime")?;
    rt.block_on(async move {
        let addr = SocketAddr::new(a.host, a.port);
        let listener = tokio::net::TcpListener::bind(addr)
            .await
            .with_context(|| format!("cannot listen on --host {} --port {}", a.host, a.port))?;
        let bound = listener.local_addr()?;
        let url = format!("http://{bound}/");
        outln!("cellsurf serve: listening on {url}")?;
        std::io::stdout().flush().ok();
        if a.open {
            open_browser(&url);
        }
        let config = ServerConfig {
            max_sessions: a.max_sessions as usize,
            ..ServerConfig::default()
        };
        serve(listener, config).await.context("server stopped")
    })
}

fn open_browser(url: &str) {
    let opener = if cfg!(target_os = "macos") {
        "open"
    } else if cfg!(windows) {
        "explorer"
    } else {
        "xdg-open"
    };
    if let Err(e) = std::process::Command::new(opener).arg(url).spawn() {
        super::conv::err_line(format_args!(
            "--open: cannot start {opener} ({e}); open {url} yourself"
        ));
    }
}

/// An address to bind: an IPv4 or IPv6 address, or `localhost` (127.0.0.1).
fn parse_host(s: &str) -> Result<std::net::IpAddr, String> {
    if s.eq_ignore_ascii_case("localhost") {
        return Ok(std::net::IpAddr::V4(std::net::Ipv4Addr::LOCALHOST));
    }
    s.parse().map_err(|_| {
        format!("'{s}' is not an address to bind: expected an IP address (127.0.0.1, ::1, 0.0.0.0) or localhost")
    })
}

#[cfg(test)]
mod tests {
    use super::parse_max_sessions;

    #[test]
    fn max_sessions_takes_whole_numbers_in_its_range() {
        assert_eq!(parse_max_sessions("1e2"), Ok(100));
        assert_eq!(parse_max_sessions("1024"), Ok(1024));
        for bad in ["0", "1025", "1.5", "-1"] {
            let e = parse_max_sessions(bad).unwrap_err();
            assert!(
                e.contains("1 to 1024") || e.contains("not a whole"),
                "{bad}: {e}"
            );
        }
        // the value as typed, quoted, whether the type holds it or not
        for bad in ["0", "1025", "1e19"] {
            assert_eq!(
                parse_max_sessions(bad),
                Err(format!(
                    "'{bad}' is out of range: expected 1 to 1024 sessions"
                ))
            );
        }
    }
}
