//! `contactmap serve` over real HTTP on loopback: the API's answers, what no request may reach
//! (paths outside the files served), range requests on a served .hic, CORS, 32 clients at once,
//! and a clean stop on Ctrl-C.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use crate::data;

/// A server started on a free port; stopped with SIGINT when dropped.
struct Server {
    child: Child,
    port: u16,
    stderr: Vec<String>,
}

impl Server {
    fn start(args: &[&str]) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_contactmap"))
            .arg("serve")
            .args(args)
            .args(["--port", "0"])
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
        let mut stderr = Vec::new();
        let port = loop {
            let line = lines.next().expect("serve printed its URL").unwrap();
            stderr.push(line.clone());
            if let Some(url) = line.strip_prefix("contactmap serve: http://") {
                let port = url.trim_end_matches('/').rsplit(':').next().unwrap();
                break port.parse().unwrap();
            }
        };
        // keep reading standard error so that the server never blocks on it
        std::thread::spawn(move || for _ in lines {});
        Server {
            child,
            port,
            stderr,
        }
    }

    /// `GET target` (sent as written: no normalisation of `..`) with extra header lines; the
    /// status, the header block and the body.
    fn get(&self, target: &str, headers: &str) -> (u16, String, Vec<u8>) {
        let mut stream = TcpStream::connect(("127.0.0.1", self.port)).unwrap();
        stream
            .set_read_timeout(Some(Duration::from_secs(60)))
            .unwrap();
        write!(
            stream,
            "GET {target} HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n{headers}\r\n"
        )
        .unwrap();
        let mut response = Vec::new();
        stream.read_to_end(&mut response).unwrap();
        let split = response
            .windows(4)
            .position(|w| w == b"\r\n\r\n")
            .expect("a header block");
        let head = String::from_utf8_lossy(&response[..split]).into_owned();
        let status = head.split(' ').nth(1).unwrap().parse().unwrap();
        (status, head, response[split + 4..].to_vec())
    }

    fn json(&self, target: &str) -> (u16, serde_json::Value) {
        let (status, _, body) = self.get(target, "");
        (status, serde_json::from_slice(&body).unwrap())
    }

    /// SIGINT, as Ctrl-C sends; the exit status.
    fn interrupt(mut self) -> std::process::ExitStatus {
        let pid = self.child.id().to_string();
        assert!(
            Command::new("kill")
                .args(["-INT", &pid])
                .status()
                .unwrap()
                .success()
        );
        self.child.wait().unwrap()
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[test]
fn serve_answers_higlass_and_nothing_outside_its_files() {
    let hic = data("hic_test_file.hic");
    let server = Server::start(&[&data("cooler_test_file.mcool"), &hic]);
    assert!(
        server
            .stderr
            .iter()
            .any(|l| l.contains("cooler_test_file <- "))
    );
    let (status, list) = server.json("/api/v1/tilesets/");
    assert_eq!(status, 200);
    assert_eq!(list["count"], 2);
    assert_eq!(list["results"][1]["uuid"], "hic_test_file");
    assert_eq!(list["results"][1]["filetype"], "hic");

    let (status, info) = server.json("/api/v1/tileset_info/?d=cooler_test_file");
    assert_eq!(status, 200);
    assert_eq!(
        info["cooler_test_file"]["resolutions"],
        serde_json::json!([100000, 1000000])
    );

    // tiles, with the transform and without, CORS on every answer
    let (status, head, body) = server.get(
        "/api/v1/tiles/?d=cooler_test_file.1.0.0&d=cooler_test_file.1.0.0.KR&d=hic_test_file.0.0.0",
        "",
    );
    assert_eq!(status, 200);
    assert!(
        head.to_ascii_lowercase()
            .contains("access-control-allow-origin: *"),
        "{head}"
    );
    let tiles: serde_json::Value = serde_json::from_slice(&body).unwrap();
    for id in [
        "cooler_test_file.1.0.0",
        "cooler_test_file.1.0.0.KR",
        "hic_test_file.0.0.0",
    ] {
        assert!(
            tiles[id]["dense"].as_str().is_some_and(|d| d.len() > 1000),
            "{id}"
        );
    }

    // paths and parameters that try to leave the files served
    for target in [
        "/../../../../etc/passwd",
        "/%2e%2e/%2e%2e/etc/passwd",
        "/files/..%2f..%2f..%2fetc%2fpasswd",
        "/files/../../etc/passwd",
        "/files//etc/passwd",
        "/files/cooler_test_file.mcool",
        "/web/../Cargo.toml",
        "/api/v1/chrom-sizes/?id=..%2F..%2Fetc%2Fpasswd",
        "/api/v1/tiles/?d=%2Fetc%2Fpasswd.0.0.0",
        "/api/v1/tileset_info/?d=..%2Fdata%2Fhic_test_file",
    ] {
        let (status, _, body) = server.get(target, "");
        let text = String::from_utf8_lossy(&body);
        assert!(!text.contains("root:"), "{target}: {text}");
        assert!(
            [400, 404].contains(&status) || text.contains("No such tileset"),
            "{target}: {status} {text}"
        );
    }
    let (status, _, _) = server.get("/api/v1/tiles/?d=cooler_test_file.1.x.0", "");
    assert_eq!(status, 400);

    // the .hic's bytes, by range, equal to the file's
    let bytes = std::fs::read(&hic).unwrap();
    let (status, head, body) = server.get("/files/hic_test_file.hic", "Range: bytes=100-1123\r\n");
    assert_eq!(status, 206, "{head}");
    assert_eq!(body, &bytes[100..1124]);
    assert!(
        head.contains(&format!("bytes 100-1123/{}", bytes.len())),
        "{head}"
    );
    let (status, _, body) = server.get("/files/hic_test_file.hic", "Range: bytes=-16\r\n");
    assert_eq!((status, body.as_slice()), (206, &bytes[bytes.len() - 16..]));
    let (status, _, _) = server.get("/files/hic_test_file.hic", "Range: bytes=99999999-\r\n");
    assert_eq!(status, 416);

    // 32 clients at once, each walking its own tiles
    let port = server.port;
    let clients: Vec<_> = (0..32)
        .map(|c| {
            std::thread::spawn(move || {
                let server = Server {
                    child: Command::new("true").spawn().unwrap(),
                    port,
                    stderr: Vec::new(),
                };
                for x in 0..6 {
                    let target = format!(
                        "/api/v1/tiles/?d=cooler_test_file.1.{x}.{}&d=cooler_test_file.0.0.0",
                        (x + c) % 6
                    );
                    let (status, tiles) = server.json(&target);
                    assert_eq!(status, 200, "{target}");
                    assert_eq!(tiles.as_object().unwrap().len(), 2, "{target}");
                }
            })
        })
        .collect();
    for client in clients {
        client.join().unwrap();
    }

    let status = server.interrupt();
    assert!(
        status.success(),
        "Ctrl-C stops the server cleanly: {status:?}"
    );
}

#[test]
fn serve_refuses_what_it_cannot_serve_and_warns_off_loopback() {
    let err = crate::run_err(&[
        "serve",
        &data("yeast.10kb.cool"),
        "--port",
        "0",
        "--web",
        "/nonexistent",
    ]);
    assert!(err.contains("/nonexistent"), "{err}");
    let err = crate::run_err(&["serve", &data("hg19.GM12878-MboI.matrix.2000kb.bg2.gz")]);
    assert!(err.contains("not a .cool, .mcool, .hic, .bed"), "{err}");
    let err = crate::run_err(&[
        "serve",
        &format!("{}::/resolutions/100000", data("cooler_test_file.mcool")),
    ]);
    assert!(err.contains("whole files"), "{err}");
    // a table's track names its column, or takes the one contactmap's tables lead with
    let dir = tempfile::tempdir().unwrap();
    let table = crate::write(
        dir.path(),
        "ins.tsv",
        "chrom\tstart\tend\tother\nchrII\t0\t10000\t1.5\n",
    );
    let err = crate::run_err(&["serve", &data("yeast.10kb.cool"), &table]);
    assert!(
        err.contains("no column to show by default") && err.contains("ins.tsv::COLUMN"),
        "{err}"
    );
    let column = format!("{table}::other");
    let server = Server::start(&[&data("yeast.10kb.cool"), &column, "--bind", "0.0.0.0"]);
    let (status, tiles) = server.json("/api/v1/tiles/?d=ins.0.0");
    assert_eq!(status, 200);
    assert_eq!(tiles["ins.0.0"]["dtype"], "float32");
    assert!(
        server
            .stderr
            .iter()
            .any(|l| l.contains("warning: listening on 0.0.0.0")),
        "{:?}",
        server.stderr
    );
    let (status, info) = server.json("/api/v1/tileset_info/?d=yeast");
    assert_eq!(status, 200);
    assert_eq!(info["yeast"]["resolutions"], serde_json::json!([10000]));
}
