//! Who may talk to the server: the token printed with the URL (a cookie after the page's first
//! load, or a header for curl), a `Host` naming the address it listens on (DNS rebinding) and
//! no foreign `Origin` (cross-site requests). Every request passes [`check`] first.
use std::io::Read;
use std::net::SocketAddr;

use axum::http::{header, HeaderMap, StatusCode};

/// The cookie that carries the token after the page's first load.
pub const COOKIE: &str = "shadelab_token";
/// The header that carries it for other clients (curl).
pub const HEADER: &str = "x-shadelab-token";

/// The server's secret and the hosts it answers to.
#[derive(Debug, Clone)]
pub struct Guard {
    pub token: String,
    /// `Host` values accepted: the listening address and its loopback names, with the port.
    hosts: Vec<String>,
}

/// A request refused: its status and why.
pub type Refusal = (StatusCode, String);

impl Guard {
    /// A new token (128 bits of the kernel's random source) for a server listening on `addr`.
    pub fn new(addr: SocketAddr) -> std::io::Result<Guard> {
        let mut bytes = [0u8; 16];
        std::fs::File::open("/dev/urandom")?.read_exact(&mut bytes)?;
        let token = bytes.iter().map(|b| format!("{b:02x}")).collect();
        let port = addr.port();
        let mut hosts = vec![
            format!("127.0.0.1:{port}"),
            format!("localhost:{port}"),
            format!("[::1]:{port}"),
        ];
        let own = match addr {
            SocketAddr::V4(a) => format!("{}:{port}", a.ip()),
            SocketAddr::V6(a) => format!("[{}]:{port}", a.ip()),
        };
        if !hosts.contains(&own) {
            hosts.push(own);
        }
        Ok(Guard { token, hosts })
    }

    /// The URL to open: the listening address (loopback by name when it is a wildcard) with the
    /// token.
    pub fn url(&self, addr: SocketAddr) -> String {
        let host = match addr {
            a if a.ip().is_unspecified() => format!("127.0.0.1:{}", a.port()),
            SocketAddr::V4(a) => a.to_string(),
            SocketAddr::V6(a) => format!("[{}]:{}", a.ip(), a.port()),
        };
        format!("http://{host}/?token={}", self.token)
    }

    /// Whether a request with `headers` (and `query_token`, the page's `?token=`) may be
    /// answered: 403 for a foreign host or origin, 401 without the token.
    pub fn check(
        &self,
        headers: &HeaderMap,
        query_token: Option<&str>,
    ) -> std::result::Result<(), Refusal> {
        let host = headers
            .get(header::HOST)
            .and_then(|h| h.to_str().ok())
            .unwrap_or("");
        if !self.hosts.iter().any(|h| h.eq_ignore_ascii_case(host)) {
            return Err((
                StatusCode::FORBIDDEN,
                format!(
                    "Host {host:?} is not this server's address ({}): refused against DNS \
                     rebinding",
                    self.hosts.join(", ")
                ),
            ));
        }
        if let Some(origin) = headers.get(header::ORIGIN) {
            let origin = origin.to_str().unwrap_or("");
            let ours = self
                .hosts
                .iter()
                .any(|h| origin.eq_ignore_ascii_case(&format!("http://{h}")));
            if !ours {
                return Err((
                    StatusCode::FORBIDDEN,
                    format!(
                        "Origin {origin:?} is not this server: cross-site requests are refused"
                    ),
                ));
            }
        }
        let given = [
            query_token,
            headers.get(HEADER).and_then(|h| h.to_str().ok()),
            cookie(headers, COOKIE),
        ];
        if given.into_iter().flatten().any(|t| same(t, &self.token)) {
            Ok(())
        } else {
            Err((
                StatusCode::UNAUTHORIZED,
                "no token: open the URL `shadelab explore` printed (it ends in ?token=...), or \
                 send the header X-Shadelab-Token"
                    .into(),
            ))
        }
    }

    /// The `Set-Cookie` value that keeps the token for the page's own requests.
    pub fn set_cookie(&self) -> String {
        format!("{COOKIE}={}; HttpOnly; SameSite=Strict; Path=/", self.token)
    }
}

/// The value of cookie `name` in the request's `Cookie` headers (RFC 6265 `name=value` pairs
/// separated by `; `).
fn cookie<'h>(headers: &'h HeaderMap, name: &str) -> Option<&'h str> {
    headers
        .get_all(header::COOKIE)
        .iter()
        .filter_map(|v| v.to_str().ok())
        .flat_map(|v| v.split(';'))
        .find_map(|pair| {
            let (k, v) = pair.trim().split_once('=')?;
            (k == name).then_some(v)
        })
}

/// `a == b` in a time that does not depend on where they differ.
fn same(a: &str, b: &str) -> bool {
    a.len() == b.len()
        && a.bytes()
            .zip(b.bytes())
            .fold(0u8, |acc, (x, y)| acc | (x ^ y))
            == 0
}

#[cfg(test)]
mod tests {
    use super::*;
    use axum::http::HeaderValue;

    fn guard() -> Guard {
        Guard::new("127.0.0.1:4000".parse().unwrap()).unwrap()
    }

    fn headers(pairs: &[(&'static str, &str)]) -> HeaderMap {
        let mut h = HeaderMap::new();
        for (k, v) in pairs {
            h.append(*k, HeaderValue::from_str(v).unwrap());
        }
        h
    }

    #[test]
    fn only_the_token_on_our_host_from_our_origin_passes() {
        let g = guard();
        let t = g.token.clone();
        let ok = |h: &HeaderMap, q: Option<&str>| g.check(h, q).map_err(|e| e.0);
        let host = ("host", "127.0.0.1:4000");
        assert_eq!(
            ok(&headers(&[host, ("x-shadelab-token", &t)]), None),
            Ok(())
        );
        let cookie = format!("a=b; {COOKIE}={t}");
        assert_eq!(ok(&headers(&[host, ("cookie", &cookie)]), None), Ok(()));
        assert_eq!(ok(&headers(&[host]), Some(&t)), Ok(()));
        assert_eq!(
            ok(&headers(&[("host", "localhost:4000")]), Some(&t)),
            Ok(())
        );
        let page = ("origin", "http://127.0.0.1:4000");
        assert_eq!(ok(&headers(&[host, page]), Some(&t)), Ok(()));
        // teeth: no token, a wrong one, a foreign host, a foreign origin
        assert_eq!(ok(&headers(&[host]), None), Err(StatusCode::UNAUTHORIZED));
        let wrong = format!("{}0", &t[..t.len() - 1]);
        let wrong = if wrong == t {
            format!("{}1", &t[..t.len() - 1])
        } else {
            wrong
        };
        assert_eq!(
            ok(&headers(&[host]), Some(&wrong)),
            Err(StatusCode::UNAUTHORIZED)
        );
        let evil = ("host", "evil.example:4000");
        assert_eq!(ok(&headers(&[evil]), Some(&t)), Err(StatusCode::FORBIDDEN));
        let other_port = ("host", "127.0.0.1:4001");
        assert_eq!(
            ok(&headers(&[other_port]), Some(&t)),
            Err(StatusCode::FORBIDDEN)
        );
        let site = ("origin", "http://evil.example");
        assert_eq!(
            ok(&headers(&[host, site]), Some(&t)),
            Err(StatusCode::FORBIDDEN)
        );
    }

    #[test]
    fn two_servers_get_two_tokens() {
        assert_ne!(guard().token, guard().token);
        assert_eq!(guard().token.len(), 32);
    }
}
