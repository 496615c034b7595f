//! A small static file server for a view folder, on 127.0.0.1 only.
//!
//! It answers GET and HEAD for files under the view folder and nothing else: the request path
//! is percent-decoded and split into segments; a segment that is empty, `.`, `..`, or holds a
//! `\` or a NUL is refused (403), and the resolved file must still lie inside the folder once
//! symbolic links are resolved. So neither `/../x`, `/%2e%2e/x`, `/a/..%2f..%2fx` nor a link
//! out of the folder reaches a file outside it. One thread per connection, one request per
//! connection (`Connection: close`): the page's few hundred requests come from one browser on
//! the same machine.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{Ipv4Addr, SocketAddr, TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::ViewError;

/// Longest request head accepted.
const MAX_HEAD: usize = 16 * 1024;

/// A bound, not yet serving, server.
pub struct Server {
    listener: TcpListener,
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
        Ok(Server { listener, root })
    }

    /// The address it listens on.
    pub fn address(&self) -> SocketAddr {
        self.listener.local_addr().expect("a bound listener has an address")
    }

    /// The page's URL.
    pub fn url(&self) -> String {
        format!("http://{}/", self.address())
    }

    /// Serves until the process ends.
    pub fn run(self) {
        for stream in self.listener.incoming().flatten() {
            let root = self.root.clone();
            std::thread::spawn(move || {
                let _ = answer(&root, stream);
            });
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

/// An HTTP response: status line, type and body.
struct Response {
    status: &'static str,
    content_type: &'static str,
    body: Vec<u8>,
}

impl Response {
    fn text(status: &'static str, message: &str) -> Response {
        Response {
            status,
            content_type: "text/plain; charset=utf-8",
            body: format!("{message}\n").into_bytes(),
        }
    }
}

fn answer(root: &Path, mut stream: TcpStream) -> std::io::Result<()> {
    stream.set_read_timeout(Some(Duration::from_secs(10)))?;
    let head = read_head(&stream)?;
    let (method, target) = parse_request_line(&head);
    let response = match method {
        "GET" | "HEAD" => respond(root, target),
        _ => Response::text("405 Method Not Allowed", "only GET and HEAD"),
    };
    let mut out = format!(
        "HTTP/1.1 {}\r\nContent-Type: {}\r\nContent-Length: {}\r\nCache-Control: no-cache\r\n\
         X-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n",
        response.status,
        response.content_type,
        response.body.len()
    )
    .into_bytes();
    if method != "HEAD" {
        out.extend_from_slice(&response.body);
    }
    stream.write_all(&out)?;
    stream.flush()
}

fn read_head(stream: &TcpStream) -> std::io::Result<String> {
    // At most MAX_HEAD bytes in all, however long a line the client sends.
    let mut reader = BufReader::new(stream.take(MAX_HEAD as u64 + 1));
    let mut head = String::new();
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line)? == 0 || line == "\r\n" || line == "\n" || head.len() > MAX_HEAD {
            return Ok(head);
        }
        head.push_str(&line);
    }
}

fn parse_request_line(head: &str) -> (&str, &str) {
    let mut words = head.lines().next().unwrap_or("").split_whitespace();
    (words.next().unwrap_or(""), words.next().unwrap_or(""))
}

fn respond(root: &Path, target: &str) -> Response {
    let Some(path) = resolve(root, target) else {
        return Response::text("403 Forbidden", "outside the view folder");
    };
    match karst_artifact::files::read_regular(&path, karst_artifact::files::MAX_DATA_BYTES) {
        Ok(body) => Response { status: "200 OK", content_type: content_type(&path), body },
        Err(_) => Response::text("404 Not Found", "no such file in the view"),
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
    use std::io::Read;

    /// A view folder with index.html and data/a.json, beside a secret file.
    fn fixture(name: &str) -> karst_testkit::Scratch {
        let dir = karst_testkit::scratch(&format!("view-server-{name}"));
        std::fs::create_dir_all(dir.join("view/data")).unwrap();
        std::fs::write(dir.join("view/index.html"), "<html>karst</html>").unwrap();
        std::fs::write(dir.join("view/data/a.json"), "{\"a\":1}").unwrap();
        std::fs::write(dir.join("secret.txt"), "SECRET").unwrap();
        dir
    }

    /// Sends one raw request and returns the status code and the body.
    fn get(address: SocketAddr, request: &str) -> (u16, String) {
        let mut stream = TcpStream::connect(address).unwrap();
        stream.write_all(request.as_bytes()).unwrap();
        let mut text = String::new();
        stream.read_to_string(&mut text).unwrap();
        let status = text.split_whitespace().nth(1).unwrap().parse().unwrap();
        (status, text.split("\r\n\r\n").nth(1).unwrap_or("").to_string())
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
        assert_eq!(get(address, "GET / HTTP/1.1\r\n\r\n"), (200, "<html>karst</html>".into()));
        assert_eq!(get(address, "GET /data/a.json?x=1 HTTP/1.1\r\n\r\n"), (200, "{\"a\":1}".into()));
        assert_eq!(get(address, "GET /data/%61.json HTTP/1.1\r\n\r\n").0, 200);
        assert_eq!(get(address, "GET /data/none.json HTTP/1.1\r\n\r\n").0, 404);
        assert_eq!(get(address, "HEAD / HTTP/1.1\r\n\r\n"), (200, String::new()));
        assert_eq!(get(address, "POST / HTTP/1.1\r\n\r\n").0, 405);
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
            let (status, body) = get(address, &format!("GET {target} HTTP/1.1\r\n\r\n"));
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
