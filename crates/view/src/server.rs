//! A small static file server for a view folder, on 127.0.0.1 only, on `tiny_http` (the HTTP/1.1
//! parsing, keep-alive connections and response framing are that crate's).
//!
//! It answers GET and HEAD for files under the view folder and nothing else (405): the request
//! path is percent-decoded and split into segments; a segment that is empty, `.`, `..`, or holds
//! a `\` or a NUL is refused (403), and the resolved file must still lie inside the folder once
//! symbolic links are resolved. So neither `/../x`, `/%2e%2e/x`, `/a/..%2f..%2fx` nor a link
//! out of the folder reaches a file outside it. A missing file is a 404. Files are streamed
//! with their length (no chunked encoding), typed by extension, never cached by the browser
//! (`Cache-Control: no-cache`: a view rewritten by a new run is reloaded) nor sniffed. A few
//! threads answer the page's few hundred requests from one browser on the same machine.

use std::net::{Ipv4Addr, SocketAddr, TcpListener};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use tiny_http::{Header, Method, Request, Response, StatusCode};

use crate::ViewError;

/// Threads answering requests.
const WORKERS: usize = 4;

/// A bound, not yet serving, server.
pub struct Server {
    http: Arc<tiny_http::Server>,
    address: SocketAddr,
    root: PathBuf,
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
        let listen = |source: std::io::Error| ViewError::Listen { port, source };
        let address = listener.local_addr().map_err(listen)?;
        let http =
            tiny_http::Server::from_listener(listener, None).map_err(|e| listen(std::io::Error::other(e)))?;
        Ok(Server { http: Arc::new(http), address, root })
    }

    /// The address it listens on.
    pub fn address(&self) -> SocketAddr {
        self.address
    }

    /// The page's URL.
    pub fn url(&self) -> String {
        format!("http://{}/", self.address())
    }

    /// Serves until the process ends.
    pub fn run(self) {
        let workers: Vec<_> = (0..WORKERS)
            .map(|_| {
                let (http, root) = (Arc::clone(&self.http), self.root.clone());
                std::thread::spawn(move || {
                    for request in http.incoming_requests() {
                        answer(&root, request);
                    }
                })
            })
            .collect();
        for worker in workers {
            let _ = worker.join();
        }
    }
}

/// Binds, prints the URL and serves `view_dir` until Ctrl-C.
pub fn serve(view_dir: &Path, port: u16) -> Result<(), ViewError> {
    let server = Server::bind(view_dir, port)?;
    println!("serving {} at {}  (Ctrl-C stops)", view_dir.display(), server.url());
    server.run();
    Ok(())
}

/// Answers one request; a client that went away is no error of the server's.
fn answer(root: &Path, request: Request) {
    let response = match request.method() {
        Method::Get | Method::Head => respond(root, request.url()),
        _ => text(405, "only GET and HEAD"),
    };
    let _ = request.respond(response);
}

/// The response to a GET or HEAD of `target`: the file, 403 outside the folder, 404 missing.
fn respond(root: &Path, target: &str) -> Response<Box<dyn std::io::Read + Send>> {
    let Some(path) = resolve(root, target) else {
        return text(403, "outside the view folder");
    };
    match karst_artifact::files::open_regular(&path, karst_artifact::files::MAX_DATA_BYTES) {
        Ok((file, length)) => with_headers(
            Response::new(StatusCode(200), Vec::new(), Box::new(file), usize::try_from(length).ok(), None),
            content_type(&path),
        ),
        Err(_) => text(404, "no such file in the view"),
    }
}

/// A plain-text error page.
fn text(status: u16, message: &str) -> Response<Box<dyn std::io::Read + Send>> {
    let body = format!("{message}\n").into_bytes();
    let length = body.len();
    with_headers(
        Response::new(
            StatusCode(status),
            Vec::new(),
            Box::new(std::io::Cursor::new(body)),
            Some(length),
            None,
        ),
        "text/plain; charset=utf-8",
    )
}

/// The headers every response carries; the length is always sent, never chunked.
fn with_headers<R: std::io::Read>(response: Response<R>, content_type: &str) -> Response<R> {
    let header = |name: &str, value: &str| {
        Header::from_bytes(name.as_bytes(), value.as_bytes()).expect("ASCII header names and values")
    };
    response
        .with_header(header("Content-Type", content_type))
        .with_header(header("Cache-Control", "no-cache"))
        .with_header(header("X-Content-Type-Options", "nosniff"))
        .with_chunked_threshold(usize::MAX)
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

    /// Sends one raw request (its request line and headers, the head's end added) on its own
    /// connection and returns the raw response.
    fn exchange(address: SocketAddr, head: &str) -> String {
        let mut stream = TcpStream::connect(address).unwrap();
        stream.set_read_timeout(Some(std::time::Duration::from_secs(20))).unwrap();
        stream
            .write_all(format!("{head}\r\nHost: localhost\r\nConnection: close\r\n\r\n").as_bytes())
            .unwrap();
        let mut text = String::new();
        stream.read_to_string(&mut text).unwrap();
        text
    }

    /// The status code and the body of the answer to a request line.
    fn get(address: SocketAddr, request_line: &str) -> (u16, String) {
        let text = exchange(address, request_line);
        let status = text.split_whitespace().nth(1).unwrap().parse().unwrap();
        (status, text.split_once("\r\n\r\n").map_or("", |(_, body)| body).to_string())
    }

    /// The value of the response header `name`, if present.
    fn header<'a>(response: &'a str, name: &str) -> Option<&'a str> {
        let head = response.split("\r\n\r\n").next().unwrap_or("");
        head.lines().find_map(|l| {
            let (key, value) = l.split_once(':')?;
            key.eq_ignore_ascii_case(name).then(|| value.trim())
        })
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
        assert_eq!(get(address, "GET / HTTP/1.1"), (200, "<html>karst</html>".into()));
        assert_eq!(get(address, "GET /data/a.json?x=1 HTTP/1.1"), (200, "{\"a\":1}".into()));
        assert_eq!(get(address, "GET /data/%61.json HTTP/1.1").0, 200);
        assert_eq!(get(address, "GET /data/none.json HTTP/1.1"), (404, "no such file in the view\n".into()));
        assert_eq!(get(address, "HEAD / HTTP/1.1"), (200, String::new()));
        assert_eq!(get(address, "POST / HTTP/1.1"), (405, "only GET and HEAD\n".into()));
        assert_eq!(get(address, "DELETE /data/a.json HTTP/1.1").0, 405);
        assert!(dir.join("view/data/a.json").is_file());
    }

    #[test]
    fn files_carry_their_type_and_length_and_are_not_cached() {
        let dir = fixture("headers");
        // Larger than tiny_http's default threshold for chunked encoding: still sent with its length.
        let big: String = (0..100_000).map(|i| char::from(b'a' + (i % 26) as u8)).collect();
        std::fs::write(dir.join("view/data/big.glb"), &big).unwrap();
        let address = spawn(&dir.join("view"));
        for (target, kind, length) in [
            ("/", "text/html; charset=utf-8", 18),
            ("/data/a.json", "application/json", 7),
            ("/data/big.glb", "model/gltf-binary", big.len()),
        ] {
            let response = exchange(address, &format!("GET {target} HTTP/1.1"));
            assert_eq!(header(&response, "Content-Type"), Some(kind), "{target}");
            assert_eq!(header(&response, "Content-Length"), Some(length.to_string().as_str()), "{target}");
            assert_eq!(header(&response, "Transfer-Encoding"), None, "{target}");
            assert_eq!(header(&response, "Cache-Control"), Some("no-cache"), "{target}");
            assert_eq!(header(&response, "X-Content-Type-Options"), Some("nosniff"), "{target}");
        }
        let response = exchange(address, "HEAD /data/big.glb HTTP/1.1");
        assert_eq!(header(&response, "Content-Length"), Some(big.len().to_string().as_str()));
        assert!(response.ends_with("\r\n\r\n"), "a HEAD answer has no body");
        assert!(get(address, "GET /data/big.glb HTTP/1.1").1 == big);
    }

    #[test]
    fn one_connection_serves_several_requests() {
        let dir = fixture("keepalive");
        let address = spawn(&dir.join("view"));
        let mut stream = TcpStream::connect(address).unwrap();
        stream.set_read_timeout(Some(std::time::Duration::from_secs(20))).unwrap();
        let request = "GET /data/a.json HTTP/1.1\r\nHost: localhost\r\n\r\n";
        stream.write_all(format!("{request}{request}").as_bytes()).unwrap();
        stream.write_all(b"GET / HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n").unwrap();
        let mut text = String::new();
        stream.read_to_string(&mut text).unwrap();
        assert_eq!(text.matches("HTTP/1.1 200").count(), 3, "{text}");
        assert_eq!(text.matches("{\"a\":1}").count(), 2, "{text}");
        assert!(text.ends_with("<html>karst</html>"), "{text}");
    }

    #[test]
    fn refuses_every_way_out_of_the_view() {
        let dir = fixture("traversal");
        std::os::unix::fs::symlink(dir.join("secret.txt"), dir.join("view/link.txt")).unwrap();
        let address = spawn(&dir.join("view"));
        for target in [
            "/../secret.txt",
            "/data/../../secret.txt",
            "/%2e%2e/secret.txt",
            "/%2E%2E/secret.txt",
            "/data/..%2f..%2fsecret.txt",
            "/data/%2e%2e%2f%2e%2e%2fsecret.txt",
            "/..%5csecret.txt",
            "//etc/passwd",
            "/%00",
            "/%zz",
            "/link.txt",
            "secret.txt",
        ] {
            let (status, body) = get(address, &format!("GET {target} HTTP/1.1"));
            assert_eq!(status, 403, "{target}");
            assert!(!body.contains("SECRET"), "{target}");
        }
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
