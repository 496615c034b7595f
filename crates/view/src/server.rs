//! A static file server for a view folder, on 127.0.0.1 only, built on tiny_http.
//!
//! tiny_http speaks HTTP/1.1 (request heads, keep-alive, pipelined requests answered in order,
//! HEAD answered without a body); this module decides what is served. It answers GET and HEAD
//! for files under the view folder and nothing else (405, `Allow: GET, HEAD`): the request
//! path is percent-decoded and split into segments; a segment that is empty, `.`, `..`, or
//! holds a `\` or a NUL is refused (403), as is a malformed escape, and the resolved file must
//! still lie inside the folder once symbolic links are resolved. So neither `/../x`,
//! `/%2e%2e/x`, `/a/..%2f..%2fx` nor a link out of the folder reaches a file outside it.
//! Every response carries its `Content-Type` (from the file's extension), `Content-Length`,
//! `Cache-Control: no-cache` and `X-Content-Type-Options: nosniff`. Each request is answered on
//! a thread of its own: the page's few hundred requests come from one browser on the same
//! machine.

use std::io::Cursor;
use std::net::{Ipv4Addr, SocketAddr, TcpListener};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use tiny_http::{Header, Method, Request, Response};

use crate::ViewError;

/// A bound, not yet serving, server.
pub struct Server {
    http: tiny_http::Server,
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
        // Bound here rather than by tiny_http, whose error does not say the port is in use.
        let listener = TcpListener::bind((Ipv4Addr::LOCALHOST, port)).map_err(|source| {
            if source.kind() == std::io::ErrorKind::AddrInUse {
                ViewError::PortInUse { port, suggestion: port.wrapping_add(1).max(1024) }
            } else {
                ViewError::Listen { port, source }
            }
        })?;
        let listen = |source| ViewError::Listen { port, source };
        let address = listener.local_addr().map_err(listen)?;
        let http =
            tiny_http::Server::from_listener(listener, None).map_err(|e| listen(std::io::Error::other(e)))?;
        Ok(Server { http, address, root })
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
        let root: Arc<Path> = self.root.into();
        for request in self.http.incoming_requests() {
            let root = Arc::clone(&root);
            std::thread::spawn(move || answer(&root, request));
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

/// What a request is answered with: status, type and body.
struct Reply {
    status: u16,
    content_type: &'static str,
    body: Vec<u8>,
}

impl Reply {
    fn text(status: u16, message: &str) -> Reply {
        Reply { status, content_type: "text/plain; charset=utf-8", body: format!("{message}\n").into_bytes() }
    }

    fn into_response(self) -> Response<Cursor<Vec<u8>>> {
        let mut response = Response::from_data(self.body)
            .with_status_code(self.status)
            // The length is known: always a Content-Length, never chunks.
            .with_chunked_threshold(usize::MAX);
        for (field, value) in [
            ("Content-Type", self.content_type),
            ("Cache-Control", "no-cache"),
            ("X-Content-Type-Options", "nosniff"),
        ] {
            response.add_header(header(field, value));
        }
        if self.status == 405 {
            response.add_header(header("Allow", "GET, HEAD"));
        }
        response
    }
}

/// A header of this module (names and values are ASCII constants).
fn header(field: &str, value: &str) -> Header {
    Header::from_bytes(field, value).expect("an ASCII header")
}

fn answer(root: &Path, request: Request) {
    let reply = match request.method() {
        Method::Get | Method::Head => respond(root, request.url()),
        _ => Reply::text(405, "only GET and HEAD"),
    };
    // A client gone meanwhile is no error of the server.
    let _ = request.respond(reply.into_response());
}

fn respond(root: &Path, target: &str) -> Reply {
    let Some(path) = resolve(root, target) else {
        return Reply::text(403, "outside the view folder");
    };
    match karst_artifact::files::read_regular(&path, karst_artifact::files::MAX_DATA_BYTES) {
        Ok(body) => Reply { status: 200, content_type: content_type(&path), body },
        Err(_) => Reply::text(404, "no such file in the view"),
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
        let mut text = String::new();
        stream.read_to_string(&mut text).unwrap();
        text
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
