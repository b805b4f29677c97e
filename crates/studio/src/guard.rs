//! Who may call the studio, checked before any route runs:
//!
//! - **Host** ([`loopback_only`]): a page that rebinds its own domain to 127.0.0.1 (DNS
//!   rebinding) sends its domain as the `Host`; a studio on loopback answers loopback names only.
//! - **Origin** ([`same_origin`]): any page the user visits can send a cross-site `POST` with a
//!   simple content type (`text/plain`, a form) without asking; the browser stamps it with the
//!   page's `Origin` and `Sec-Fetch-Site`. The API refuses requests another site made, and
//!   requests that carry a body must say `application/json` (or be an upload's `PUT`), which a
//!   cross-site page cannot send without a CORS preflight the studio never grants.
//! - **Token** ([`token`]): a studio other machines can reach asks for a secret, given once as
//!   `?token=` in the address `relief serve` prints (kept in a `SameSite=Strict` cookie), or as
//!   `Authorization: Bearer` by scripts.
//! - **Framing** ([`headers`]): no page may frame the studio (click-jacking).

use axum::extract::Request;
use axum::http::{HeaderMap, HeaderValue, Method, StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use crate::error::ApiError;

/// The cookie that carries the token (its name ends with the port, so that studios on two ports
/// of one machine keep theirs apart).
const COOKIE: &str = "relief_token";

/// Refuses (403) a request whose `Host` header names anything but a loopback address. A request
/// without a `Host` (not from a browser) passes.
pub(crate) async fn loopback_only(request: Request, next: Next) -> Response {
    let host = request.headers().get(header::HOST).map(|h| h.to_str().unwrap_or_default());
    if host.is_none_or(is_loopback_host) {
        next.run(request).await
    } else {
        let error = "the studio answers requests to localhost only (start it with --host to serve others)";
        ApiError::new(StatusCode::FORBIDDEN, error).into_response()
    }
}

/// `localhost`, `127.x.x.x`, `[::1]` or `[::ffff:127.x.x.x]`, with or without a port.
pub(crate) fn is_loopback_host(host: &str) -> bool {
    let name = match host.strip_prefix('[') {
        Some(rest) => rest.split(']').next().unwrap_or_default(),
        None => host.rsplit_once(':').map_or(host, |(name, _)| name),
    };
    name.eq_ignore_ascii_case("localhost")
        || name.parse::<std::net::IpAddr>().is_ok_and(|ip| ip.to_canonical().is_loopback())
}

/// Refuses (403) an API request that another site's page made, and (415) a body that is not
/// declared JSON where the route reads JSON. The page itself and tools without a browser
/// (`curl`, scripts: no `Origin`, no `Sec-Fetch-Site`) pass.
pub(crate) async fn same_origin(request: Request, next: Next) -> Response {
    match check_origin(request.method(), request.uri().path(), request.headers()) {
        Ok(()) => next.run(request).await,
        Err(error) => error.into_response(),
    }
}

/// Why [`same_origin`] refuses a request, if it does.
fn check_origin(method: &Method, path: &str, headers: &HeaderMap) -> Result<(), ApiError> {
    let changes = !matches!(*method, Method::GET | Method::HEAD | Method::OPTIONS);
    if !path.starts_with("/api/") && !changes {
        // The page's own files: a link from anywhere may open the studio.
        return Ok(());
    }
    let text = |name: header::HeaderName| headers.get(name).map(|v| v.to_str().unwrap_or("?"));
    let cross = |why: String| {
        let error = format!("{why}: the studio answers its own page only (a cross-site request is refused)");
        Err(ApiError::new(StatusCode::FORBIDDEN, error))
    };
    if let Some(site) = text(header::HeaderName::from_static("sec-fetch-site"))
        && !matches!(site, "same-origin" | "none")
    {
        return cross(format!("Sec-Fetch-Site {site}"));
    }
    if let Some(origin) = text(header::ORIGIN) {
        let own = text(header::HOST).is_some_and(|host| origin == format!("http://{host}"));
        if !own {
            return cross(format!("Origin {origin}"));
        }
    }
    let upload = *method == Method::PUT && path.starts_with("/api/files/");
    if changes && !upload && !is_json(text(header::CONTENT_TYPE)) {
        let error = "send the request with Content-Type: application/json";
        return Err(ApiError::new(StatusCode::UNSUPPORTED_MEDIA_TYPE, error));
    }
    Ok(())
}

/// `application/json`, with or without parameters (`; charset=utf-8`).
fn is_json(content_type: Option<&str>) -> bool {
    content_type.and_then(|t| t.split(';').next()).is_some_and(|t| t.trim().eq_ignore_ascii_case("application/json"))
}

/// Answers only requests that carry `secret`: as `?token=` (which sets the cookie and
/// redirects to the same path without it), as the cookie, or as `Authorization: Bearer`.
pub(crate) async fn token(secret: std::sync::Arc<str>, request: Request, next: Next) -> Response {
    let headers = request.headers();
    if let Some(given) = query_token(request.uri().query()) {
        if !same_secret(given, &secret) {
            return refuse_token("the address's token is wrong");
        }
        // The token leaves the address bar (and the history) for a cookie.
        let cookie = format!("{}={secret}; Path=/; HttpOnly; SameSite=Strict", cookie_name(headers));
        let to = request.uri().path().to_owned();
        let mut response = (StatusCode::SEE_OTHER, [(header::LOCATION, to)]).into_response();
        if let Ok(value) = HeaderValue::from_str(&cookie) {
            response.headers_mut().insert(header::SET_COOKIE, value);
        }
        return response;
    }
    let bearer = headers
        .get(header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.strip_prefix("Bearer "))
        .is_some_and(|given| same_secret(given.trim(), &secret));
    let name = cookie_name(headers);
    let cookie = cookies(headers).any(|(key, value)| key == name && same_secret(value, &secret));
    if bearer || cookie {
        next.run(request).await
    } else {
        refuse_token("this studio needs its token: open the address `relief serve` printed (…/?token=…)")
    }
}

/// 401 with `why`.
fn refuse_token(why: &str) -> Response {
    ApiError::new(StatusCode::UNAUTHORIZED, why).into_response()
}

/// The `token` parameter of a query string.
fn query_token(query: Option<&str>) -> Option<&str> {
    query?.split('&').find_map(|pair| pair.strip_prefix("token="))
}

/// The cookie's name for the port the request was addressed to.
fn cookie_name(headers: &HeaderMap) -> String {
    let host = headers.get(header::HOST).and_then(|h| h.to_str().ok()).unwrap_or_default();
    let port = host.rsplit_once(':').map(|(_, p)| p).filter(|p| p.bytes().all(|b| b.is_ascii_digit()));
    format!("{COOKIE}_{}", port.unwrap_or("80"))
}

/// The `name=value` pairs of every `Cookie` header.
fn cookies(headers: &HeaderMap) -> impl Iterator<Item = (&str, &str)> {
    headers
        .get_all(header::COOKIE)
        .iter()
        .filter_map(|v| v.to_str().ok())
        .flat_map(|v| v.split(';'))
        .filter_map(|pair| pair.trim().split_once('='))
}

/// Whether `given` is `secret`, compared in time independent of where they differ.
fn same_secret(given: &str, secret: &str) -> bool {
    let (a, b) = (given.as_bytes(), secret.as_bytes());
    a.len() == b.len() && a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

/// A new secret: 32 random bytes from the operating system, as 64 hex digits.
pub(crate) fn new_token() -> Result<String, getrandom::Error> {
    const HEX: &[u8; 16] = b"0123456789abcdef";
    let mut bytes = [0u8; 32];
    getrandom::fill(&mut bytes)?;
    Ok(bytes.iter().flat_map(|b| [HEX[usize::from(b >> 4)], HEX[usize::from(b & 15)]]).map(char::from).collect())
}

/// Adds the headers that keep other pages from framing the studio or sniffing its types.
pub(crate) async fn headers(request: Request, next: Next) -> Response {
    let mut response = next.run(request).await;
    let headers = response.headers_mut();
    headers.insert(header::X_FRAME_OPTIONS, HeaderValue::from_static("DENY"));
    headers.insert(header::CONTENT_SECURITY_POLICY, HeaderValue::from_static("frame-ancestors 'none'"));
    headers.insert(header::X_CONTENT_TYPE_OPTIONS, HeaderValue::from_static("nosniff"));
    headers.insert(header::REFERRER_POLICY, HeaderValue::from_static("no-referrer"));
    response
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_loopback_hosts_pass() {
        for host in [
            "localhost",
            "localhost:8737",
            "LOCALHOST:1",
            "127.0.0.1",
            "127.0.0.1:8737",
            "127.1.2.3:80",
            "[::1]:8737",
            "[::1]",
            "[::ffff:127.0.0.1]:8737",
        ] {
            assert!(is_loopback_host(host), "{host}");
        }
        for host in [
            "evil.example:8737",
            "example.com",
            "10.0.0.1:8737",
            "0.0.0.0:8737",
            "[::2]:80",
            "[::ffff:10.0.0.1]:80",
            "localhost.evil.com",
            "",
        ] {
            assert!(!is_loopback_host(host), "{host}");
        }
    }

    fn headers(pairs: &[(&'static str, &'static str)]) -> HeaderMap {
        pairs.iter().map(|(k, v)| (header::HeaderName::from_static(k), HeaderValue::from_static(v))).collect()
    }

    #[test]
    fn cross_site_requests_are_refused_and_own_ones_pass() {
        let own =
            [("host", "127.0.0.1:8737"), ("origin", "http://127.0.0.1:8737"), ("content-type", "application/json")];
        assert!(check_origin(&Method::POST, "/api/generate", &headers(&own)).is_ok());
        // No Origin at all: curl, scripts.
        assert!(
            check_origin(&Method::POST, "/api/generate", &headers(&[("content-type", "application/json")])).is_ok()
        );
        let status = |method: Method, path: &str, pairs: &[(&'static str, &'static str)]| {
            check_origin(&method, path, &headers(pairs)).err().map(|e| e.status())
        };
        let forbidden = Some(StatusCode::FORBIDDEN);
        let evil =
            [("host", "127.0.0.1:8737"), ("origin", "http://evil.example"), ("content-type", "application/json")];
        assert_eq!(status(Method::POST, "/api/generate", &evil), forbidden);
        // Another port of the same host is another origin.
        let port = [("host", "127.0.0.1:8737"), ("origin", "http://127.0.0.1:9000")];
        assert_eq!(status(Method::PUT, "/api/files/a.png", &port), forbidden);
        assert_eq!(status(Method::POST, "/api/cancel", &[("host", "localhost:1"), ("origin", "null")]), forbidden);
        // A cross-site GET of the API (an image tag starting a peak analysis) is refused too; the
        // page itself opens from anywhere.
        assert_eq!(status(Method::GET, "/api/results/1/peaks", &[("sec-fetch-site", "cross-site")]), forbidden);
        assert_eq!(status(Method::GET, "/api/info", &[("sec-fetch-site", "same-site")]), forbidden);
        assert_eq!(status(Method::GET, "/", &[("sec-fetch-site", "cross-site")]), None);
        assert_eq!(status(Method::GET, "/api/info", &[("sec-fetch-site", "same-origin")]), None);
        // A body of a simple type (a form, text/plain) is refused even from the page.
        let plain = Some(StatusCode::UNSUPPORTED_MEDIA_TYPE);
        assert_eq!(status(Method::POST, "/api/generate", &[("content-type", "text/plain")]), plain);
        assert_eq!(status(Method::POST, "/api/files/a.tif/open", &[]), plain);
        assert_eq!(status(Method::PUT, "/api/scenes/a.json", &[("content-type", "text/plain;charset=UTF-8")]), plain);
        assert_eq!(status(Method::PUT, "/api/files/a.tif", &[("content-type", "image/tiff")]), None);
        assert_eq!(status(Method::POST, "/api/cancel", &[("content-type", "Application/JSON; charset=utf-8")]), None);
    }

    #[test]
    fn tokens_are_compared_whole_and_named_by_port() {
        assert!(same_secret("abc", "abc"));
        assert!(!same_secret("abd", "abc") && !same_secret("ab", "abc") && !same_secret("abcd", "abc"));
        assert_eq!(query_token(Some("a=1&token=xyz")), Some("xyz"));
        assert_eq!(query_token(Some("tokens=1")), None);
        assert_eq!(cookie_name(&headers(&[("host", "10.0.0.2:8737")])), "relief_token_8737");
        assert_eq!(cookie_name(&headers(&[("host", "[::1]")])), "relief_token_80");
        let jar = headers(&[("cookie", "a=1; relief_token_8737=s3cret")]);
        assert_eq!(cookies(&jar).collect::<Vec<_>>(), [("a", "1"), ("relief_token_8737", "s3cret")]);
        let token = new_token().unwrap();
        assert_eq!(token.len(), 64);
        assert_ne!(token, new_token().unwrap());
    }
}
