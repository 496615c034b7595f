//! A static file server for a view folder, on 127.0.0.1 only, built on hyper's HTTP/1.1 server.
//!
//! hyper speaks HTTP/1.1 (request heads, keep-alive, pipelined requests answered in order, HEAD
//! answered without a body, `Content-Length` and `Date`); each connection is a task on one tokio
//! thread, each file is read on tokio's blocking pool, so a browser's parallel connections are
//! all served. A request head is at most [`MAX_HEAD`] bytes (a longer one is answered 431) and
//! must arrive within [`HEAD_TIMEOUT`] (else the connection is closed).
//!
//! This module decides what is served. It answers GET and HEAD for files under the view folder
//! and nothing else (405, `Allow: GET, HEAD`): the request path is percent-decoded and split into
//! segments; a segment that is empty, `.`, `..`, or holds a `\` or a NUL is refused (403), as is
//! a malformed escape, and the resolved file must still lie inside the folder once symbolic
//! links are resolved. So neither `/../x`, `/%2e%2e/x`, `/a/..%2f..%2fx` nor a link out of the
//! folder reaches a file outside it. Every response carries its `Content-Type` (from the file's
//! extension), `Cache-Control: no-cache` and `X-Content-Type-Options: nosniff`.

use std::convert::Infallible;
use std::net::{Ipv4Addr, SocketAddr, TcpListener};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

use http_body_util::Full;
use hyper::body::{Bytes, Incoming};
use hyper::header::{ALLOW, CACHE_CONTROL, CONTENT_TYPE, HeaderValue, X_CONTENT_TYPE_OPTIONS};
use hyper::{Method, Request, Response, StatusCode};
use hyper_util::rt::{TokioIo, TokioTimer};

use crate::ViewError;

/// Longest request head accepted, request line included.
pub const MAX_HEAD: usize = 16 * 1024;
/// Longest wait for a whole request head, from when the connection is ready for one (so an idle
/// kept-alive connection is closed after it too; browsers then open a new one).
pub const HEAD_TIMEOUT: Duration = Duration::from_secs(10);

/// A bound, not yet serving, server.
pub struct Server {
    listener: tokio::net::TcpListener,
    address: SocketAddr,
    root: PathBuf,
    runtime: tokio::runtime::Runtime,
}

impl Server {
    /// Binds 127.0.0.1:`port` (0: any free port) for the view folder `view_dir`.
    pub fn bind(view_dir: &Path, port: u16) -> Result<Server, ViewError> {
        let root = view_dir.canonicalize().map_err(|_| ViewError::NoFolder { dir: view_dir.into() })?;
        if !root.join("index.html").is_file() {
            let run = view_dir.parent().unwrap_or(Path::new(".")).display().to_string();
            return Err(ViewError::NoView { dir: view_dir.into(), run });
        }
        let listener = TcpListener::bind((Ipv4Addr::LOCALHOST, port)).map_err(|source| {
            if source.kind() == std::io::ErrorKind::AddrInUse {
                ViewError::PortInUse { port, suggestion: port.wrapping_add(1).max(1024) }
            } else {
                ViewError::Listen { port, source }
            }
        })?;
        let listen = |source| ViewError::Listen { port, source };
        let address = listener.local_addr().map_err(listen)?;
        listener.set_nonblocking(true).map_err(listen)?;
        let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().map_err(listen)?;
        let listener = {
            let _context = runtime.enter();
            tokio::net::TcpListener::from_std(listener).map_err(listen)?
        };
        Ok(Server { listener, address, root, runtime })
    }

    /// The address it listens on.
    pub fn address(&self) -> SocketAddr {
        self.address
    }

    /// The page's URL.
    pub fn url(&self) -> String {
        format!("http://{}/", self.address)
    }

    /// Serves until the process ends.
    pub fn run(self) {
        let Server { listener, root, runtime, .. } = self;
        let root: Arc<Path> = root.into();
        runtime.block_on(async move {
            loop {
                // A failed accept (a client gone, no file descriptor left) loses that client only.
                let Ok((stream, _)) = listener.accept().await else { continue };
                let root = Arc::clone(&root);
                tokio::spawn(async move {
                    let service =
                        hyper::service::service_fn(move |request| answer(Arc::clone(&root), request));
                    // A connection's end, orderly or not, concerns that client only.
                    let _ = hyper::server::conn::http1::Builder::new()
                        .timer(TokioTimer::new())
                        .header_read_timeout(HEAD_TIMEOUT)
                        .max_header_size(MAX_HEAD)
                        .serve_connection(TokioIo::new(stream), service)
                        .await;
                });
            }
        });
    }
}

/// Binds, prints the URL and serves `view_dir` until Ctrl-C.
pub fn serve(view_dir: &Path, port: u16) -> Result<(), ViewError> {
    let server = Server::bind(view_dir, port)?;
    println!("serving {} at {}  (Ctrl-C stops)", view_dir.display(), server.url());
    server.run();
    Ok(())
}

/// What a request is answered with: status, type and body.
struct Reply {
    status: StatusCode,
    content_type: &'static str,
    body: Vec<u8>,
}

impl Reply {
    fn text(status: StatusCode, message: &str) -> Reply {
        Reply { status, content_type: "text/plain; charset=utf-8", body: format!("{message}\n").into_bytes() }
    }

    fn into_response(self) -> Response<Full<Bytes>> {
        let mut response = Response::new(Full::new(Bytes::from(self.body)));
        *response.status_mut() = self.status;
        let headers = response.headers_mut();
        headers.insert(CONTENT_TYPE, HeaderValue::from_static(self.content_type));
        headers.insert(CACHE_CONTROL, HeaderValue::from_static("no-cache"));
        headers.insert(X_CONTENT_TYPE_OPTIONS, HeaderValue::from_static("nosniff"));
        if self.status == StatusCode::METHOD_NOT_ALLOWED {
            headers.insert(ALLOW, HeaderValue::from_static("GET, HEAD"));
        }
        response
    }
}

async fn answer(root: Arc<Path>, request: Request<Incoming>) -> Result<Response<Full<Bytes>>, Infallible> {
    let reply = if matches!(*request.method(), Method::GET | Method::HEAD) {
        let target = request.uri().to_string();
        tokio::task::spawn_blocking(move || respond(&root, &target))
            .await
            .unwrap_or_else(|_| Reply::text(StatusCode::INTERNAL_SERVER_ERROR, "the file could not be read"))
    } else {
        Reply::text(StatusCode::METHOD_NOT_ALLOWED, "only GET and HEAD")
    };
    Ok(reply.into_response())
}

fn respond(root: &Path, target: &str) -> Reply {
    let Some(path) = resolve(root, target) else {
        return Reply::text(StatusCode::FORBIDDEN, "outside the view folder");
    };
    match karst_artifact::files::read_regular(&path, karst_artifact::files::MAX_DATA_BYTES) {
        Ok(body) => Reply { status: StatusCode::OK, content_type: content_type(&path), body },
        Err(_) => Reply::text(StatusCode::NOT_FOUND, "no such file in the view"),
    }
}

/// The file a request target names, if it lies inside `root` (which is canonical).
pub fn resolve(root: &Path, target: &str) -> Option<PathBuf> {
    let path = target.split(['?', '#']).next().unwrap_or("");
    let path = path.strip_prefix('/')?;
    let decoded = percent_decode(path)?;
    let mut file = root.to_path_buf();
    let relative = if decoded.is_empty() { "index.html" } else { decoded.as_str() };
    for segment in relative.split('/') {
        if segment.is_empty() || segment == "." || segment == ".." || segment.contains(['\\', '\0']) {
            return None;
        }
        file.push(segment);
    }
    match file.canonicalize() {
        Ok(real) if real.starts_with(root) && real.is_file() => Some(real),
        Ok(_) => None,
        // A missing file: a 404 for a path that stayed inside.
        Err(_) => Some(file),
    }
}

/// `%XX` decoded; None when an escape is malformed or the result is not UTF-8.
fn percent_decode(text: &str) -> Option<String> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

fn content_type(path: &Path) -> &'static str {
    match path.extension().and_then(|e| e.to_str()).unwrap_or("") {
        "html" => "text/html; charset=utf-8",
        "js" => "text/javascript; charset=utf-8",
        "css" => "text/css; charset=utf-8",
        "json" => "application/json",
        "glb" => "model/gltf-binary",
        "png" => "image/png",
        _ => "text/plain; charset=utf-8",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::{Read, Write};
    use std::net::TcpStream;

    /// A view folder with index.html and data/a.json, beside a secret file.
    fn fixture(name: &str) -> karst_testkit::Scratch {
        let dir = karst_testkit::scratch(&format!("view-server-{name}"));
        std::fs::create_dir_all(dir.join("view/data")).unwrap();
        std::fs::write(dir.join("view/index.html"), "<html>karst</html>").unwrap();
        std::fs::write(dir.join("view/data/a.json"), "{\"a\":1}").unwrap();
        std::fs::write(dir.join("secret.txt"), "SECRET").unwrap();
        dir
    }

    /// Sends raw bytes on one connection and returns everything the server sent back until it
    /// closed the connection.
    fn exchange(address: SocketAddr, raw: &str) -> String {
        let mut stream = TcpStream::connect(address).unwrap();
        stream.write_all(raw.as_bytes()).unwrap();
        let mut bytes = Vec::new();
        // A server that refuses a request before reading all of it may reset the connection
        // after its answer: what came before the reset is the answer.
        if let Err(e) = stream.read_to_end(&mut bytes) {
            assert_eq!(e.kind(), std::io::ErrorKind::ConnectionReset, "{e}");
        }
        String::from_utf8_lossy(&bytes).into_owned()
    }

    /// One response: status code, head (status line and headers) and body.
    struct Answer {
        status: u16,
        head: String,
        body: String,
    }

    impl Answer {
        fn header(&self, field: &str) -> Option<&str> {
            self.head.lines().find_map(|line| {
                let (name, value) = line.split_once(':')?;
                name.eq_ignore_ascii_case(field).then(|| value.trim())
            })
        }
    }

    /// Sends `METHOD TARGET` (closing the connection after it) and parses the response.
    fn ask(address: SocketAddr, method: &str, target: &str) -> Answer {
        let text =
            exchange(address, &format!("{method} {target} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n"));
        let (head, body) = text.split_once("\r\n\r\n").unwrap_or((&text, ""));
        let status = head.split_whitespace().nth(1).unwrap().parse().unwrap();
        Answer { status, head: head.to_string(), body: body.to_string() }
    }

    fn get(address: SocketAddr, target: &str) -> (u16, String) {
        let answer = ask(address, "GET", target);
        (answer.status, answer.body)
    }

    fn spawn(view: &Path) -> SocketAddr {
        let server = Server::bind(view, 0).unwrap();
        let address = server.address();
        std::thread::spawn(move || server.run());
        address
    }

    #[test]
    fn serves_files_of_the_view_on_loopback() {
        let dir = fixture("files");
        let address = spawn(&dir.join("view"));
        assert!(address.ip().is_loopback());
        assert_eq!(get(address, "/"), (200, "<html>karst</html>".into()));
        assert_eq!(get(address, "/data/a.json?x=1"), (200, "{\"a\":1}".into()));
        assert_eq!(get(address, "/data/%61.json").0, 200);
        assert_eq!(get(address, "/data/none.json").0, 404);

        let page = ask(address, "GET", "/index.html");
        assert_eq!(page.header("Content-Type"), Some("text/html; charset=utf-8"));
        assert_eq!(page.header("Content-Length"), Some("18"));
        assert_eq!(page.header("Cache-Control"), Some("no-cache"));
        assert_eq!(page.header("X-Content-Type-Options"), Some("nosniff"));
        assert_eq!(ask(address, "GET", "/data/a.json").header("Content-Type"), Some("application/json"));

        let head = ask(address, "HEAD", "/data/a.json");
        assert_eq!((head.status, head.body.as_str()), (200, ""));
        assert_eq!(head.header("Content-Length"), Some("7"));

        for method in ["POST", "PUT", "DELETE", "OPTIONS"] {
            let refused = ask(address, method, "/");
            assert_eq!(refused.status, 405, "{method}");
            assert_eq!(refused.header("Allow"), Some("GET, HEAD"), "{method}");
        }
    }

    #[test]
    fn answers_requests_on_one_connection_in_order() {
        let dir = fixture("keepalive");
        let address = spawn(&dir.join("view"));
        let text = exchange(
            address,
            "GET /data/a.json HTTP/1.1\r\nHost: x\r\n\r\n\
             GET /../secret.txt HTTP/1.1\r\nHost: x\r\n\r\n\
             GET / HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n",
        );
        // A body without a final newline runs straight into the next status line.
        let statuses: Vec<&str> =
            text.match_indices("HTTP/1.1 ").map(|(i, _)| &text[i + 9..i + 12]).collect();
        assert_eq!(statuses, ["200", "403", "200"], "{text}");
        let (json, page) = (text.find("{\"a\":1}").unwrap(), text.find("<html>karst</html>").unwrap());
        assert!(json < page, "{text}");
        assert!(!text.contains("SECRET"), "{text}");
    }

    #[test]
    fn serves_a_browser_s_parallel_connections_all_at_once() {
        let dir = fixture("parallel");
        let address = spawn(&dir.join("view"));
        // Kept-alive connections, opened together: each must be answered while the others stay
        // open (a server with a fixed pool of connection threads leaves the last ones waiting).
        let connections: Vec<TcpStream> = (0..16).map(|_| TcpStream::connect(address).unwrap()).collect();
        for mut connection in &connections {
            connection.write_all(b"GET /data/a.json HTTP/1.1\r\nHost: x\r\n\r\n").unwrap();
        }
        for (i, mut connection) in connections.iter().enumerate() {
            // Not a timing assertion: a hang guard, so that a starved connection fails the test.
            connection.set_read_timeout(Some(std::time::Duration::from_secs(60))).unwrap();
            let mut answer = Vec::new();
            let mut chunk = [0; 256];
            while !String::from_utf8_lossy(&answer).ends_with("{\"a\":1}") {
                let n = connection.read(&mut chunk).unwrap_or_else(|e| panic!("connection {i}: {e}"));
                assert!(n > 0, "connection {i} closed without an answer");
                answer.extend_from_slice(&chunk[..n]);
            }
            assert!(answer.starts_with(b"HTTP/1.1 200"), "connection {i}");
        }
    }

    #[test]
    fn a_request_head_longer_than_the_bound_is_refused() {
        let dir = fixture("head");
        let address = spawn(&dir.join("view"));
        let long = format!("GET / HTTP/1.1\r\nHost: x\r\nX-Long: {}\r\n\r\n", "a".repeat(MAX_HEAD));
        let text = exchange(address, &long);
        assert!(text.starts_with("HTTP/1.1 431"), "{text}");
        assert!(!text.contains("karst"), "{text}");
        let short = format!(
            "GET / HTTP/1.1\r\nHost: x\r\nX-Long: {}\r\nConnection: close\r\n\r\n",
            "a".repeat(MAX_HEAD / 2)
        );
        assert!(exchange(address, &short).starts_with("HTTP/1.1 200"));
    }

    #[test]
    fn refuses_every_way_out_of_the_view() {
        let dir = fixture("traversal");
        std::os::unix::fs::symlink(dir.join("secret.txt"), dir.join("view/link.txt")).unwrap();
        std::os::unix::fs::symlink(&*dir, dir.join("view/up")).unwrap();
        let address = spawn(&dir.join("view"));
        for target in [
            "/../secret.txt",
            "/data/../../secret.txt",
            "/%2e%2e/secret.txt",
            "/%2E%2E/secret.txt",
            "/data/..%2f..%2fsecret.txt",
            "/data/%2e%2e%2f%2e%2e%2fsecret.txt",
            "/..%5csecret.txt",
            "/.%2e/secret.txt",
            "/./index.html",
            "//etc/passwd",
            "/%00",
            "/index.html%00",
            "/%zz",
            "/%2",
            "/link.txt",
            "/up/secret.txt",
            "secret.txt",
            "http://127.0.0.1/../secret.txt",
        ] {
            for method in ["GET", "HEAD"] {
                let answer = ask(address, method, target);
                assert_eq!(answer.status, 403, "{method} {target}");
                assert!(!answer.body.contains("SECRET"), "{method} {target}");
            }
        }
        // The same folder is served: the refusals are not a server that serves nothing.
        assert_eq!(get(address, "/data/a.json").0, 200);
    }

    #[test]
    fn a_port_in_use_is_reported_with_a_suggestion() {
        let dir = fixture("port");
        let first = Server::bind(&dir.join("view"), 0).unwrap();
        let port = first.address().port();
        let err = Server::bind(&dir.join("view"), port).err().unwrap();
        assert!(matches!(err, ViewError::PortInUse { .. }), "{err}");
        assert!(err.to_string().contains(&format!("port {port}")), "{err}");
        assert!(err.to_string().contains("--port"), "{err}");
        assert_eq!(err.exit_code(), 2);
    }

    #[test]
    fn a_folder_without_a_view_is_refused() {
        let dir = fixture("noview");
        let err = Server::bind(&dir.join("view/data"), 0).err().unwrap();
        assert!(err.to_string().contains("no view/index.html"), "{err}");
    }
}
