//! `relief serve` on the real binary: beyond loopback it prints an address with a secret and
//! answers nobody without it.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};

/// The server, killed on drop.
struct Server(Child);

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Sends `GET path` with `headers` to `port` on loopback; the status line.
fn get(port: u16, path: &str, headers: &str) -> String {
    let mut stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
    let request = format!("GET {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n{headers}\r\n");
    stream.write_all(request.as_bytes()).unwrap();
    let mut answer = String::new();
    stream.read_to_string(&mut answer).unwrap();
    answer.lines().next().unwrap_or_default().to_owned()
}

#[test]
fn served_beyond_loopback_it_asks_for_the_printed_token() {
    let workspace = tempfile::tempdir().unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(["serve", "--host", "0.0.0.0", "--port", "0", "--workspace"])
        .arg(workspace.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut server = Server(child);
    let mut line = String::new();
    BufReader::new(server.0.stdout.take().unwrap()).read_line(&mut line).unwrap();
    // "relief studio at http://0.0.0.0:PORT/?token=HEX (workspace …)"
    let url = line.split_whitespace().find(|w| w.starts_with("http://")).unwrap_or_else(|| panic!("{line}"));
    let (address, token) = url.split_once("/?token=").unwrap_or_else(|| panic!("no token in {url}"));
    assert_eq!(token.len(), 64, "{token}");
    assert!(token.bytes().all(|b| b.is_ascii_hexdigit()), "{token}");
    let port: u16 = address.rsplit(':').next().unwrap().parse().unwrap();

    assert!(get(port, "/api/info", "").contains(" 401 "), "no token");
    assert!(get(port, "/", "").contains(" 401 "), "the page too");
    assert!(get(port, "/api/info", "Authorization: Bearer 00\r\n").contains(" 401 "), "a wrong token");
    assert!(get(port, "/api/info", &format!("Authorization: Bearer {token}\r\n")).contains(" 200 "));
    assert!(get(port, &format!("/?token={token}"), "").contains(" 303 "), "the printed address");
    let cookie = format!("Cookie: relief_token_{port}={token}\r\n");
    assert!(get(port, "/", &cookie).contains(" 200 "));
}

#[test]
fn on_loopback_it_needs_no_token() {
    let workspace = tempfile::tempdir().unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(["serve", "--host", "::ffff:127.0.0.1", "--port", "0", "--workspace"])
        .arg(workspace.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut server = Server(child);
    let mut line = String::new();
    BufReader::new(server.0.stdout.take().unwrap()).read_line(&mut line).unwrap();
    assert!(!line.contains("token"), "{line}");
    let url = line.split_whitespace().find(|w| w.starts_with("http://")).unwrap_or_else(|| panic!("{line}"));
    let port: u16 = url.trim_end_matches('/').rsplit(':').next().unwrap().parse().unwrap();
    // Bound to the IPv4-mapped address, reached over IPv6.
    let mut stream = TcpStream::connect(("::ffff:127.0.0.1", port)).unwrap();
    let request = format!("GET /api/info HTTP/1.1\r\nHost: [::ffff:127.0.0.1]:{port}\r\nConnection: close\r\n\r\n");
    stream.write_all(request.as_bytes()).unwrap();
    let mut answer = String::new();
    stream.read_to_string(&mut answer).unwrap();
    assert!(answer.starts_with("HTTP/1.1 200 "), "{answer}");
}
