//! The HTTP layer (axum on tokio): one handler that carries a request to the API, to a served
//! .hic's bytes (range requests) or to the viewer page's files, and adds CORS headers. Tiles are
//! computed on tokio's blocking threads, so slow reads never hold up other clients.

use std::collections::HashMap;
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use axum::body::Body;
use axum::extract::{Request, State};
use axum::http::{HeaderMap, HeaderValue, Method, StatusCode, header};
use axum::response::Response;

use super::api::{Api, MAX_QUERY_BYTES, Reply};
use contactmap::error::{Error, Result};

/// The largest byte range of a .hic answered at once (juicebox.js and hic-straw ask for blocks of
/// kilobytes to a few megabytes).
pub const MAX_RANGE_BYTES: u64 = 64 << 20;

/// What the handler serves.
pub struct Shared {
    pub api: Api,
    pub web: Web,
    /// `/files/NAME` -> the .hic served under that name.
    pub files: HashMap<String, PathBuf>,
}

/// The viewer page's files, read into memory at start (only these names are answered).
pub struct Web {
    files: HashMap<String, (&'static str, Vec<u8>)>,
    /// Where they were read from, or `None` when no built page was found.
    pub dir: Option<PathBuf>,
}

impl Web {
    /// The built page under `dir` (its `index.html` and what lies beside it, three folders deep at
    /// most), or a page saying how to build it when `dir` is `None`.
    pub fn load(dir: Option<&Path>) -> Result<Web> {
        let mut files = HashMap::new();
        let Some(dir) = dir else {
            let page = "<!doctype html><meta charset=utf-8><title>contactmap serve</title>\
                <p>The viewer page is not built: run <code>make web</code> in contactmap's source \
                tree (it needs npm), or give <code>--web DIR</code>. The API answers at \
                <a href=\"/api/v1/tilesets/\">/api/v1/tilesets/</a>.";
            files.insert(
                "/index.html".into(),
                ("text/html; charset=utf-8", page.into()),
            );
            return Ok(Web { files, dir: None });
        };
        fn walk(
            dir: &Path,
            prefix: &str,
            depth: usize,
            files: &mut HashMap<String, (&'static str, Vec<u8>)>,
        ) -> Result<()> {
            let entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
            for entry in entries {
                let entry = entry.map_err(|e| Error::io(dir, e))?;
                let name = entry.file_name().to_string_lossy().into_owned();
                let path = entry.path();
                let kind = entry.file_type().map_err(|e| Error::io(&path, e))?;
                if kind.is_dir() && depth < 3 {
                    walk(&path, &format!("{prefix}/{name}"), depth + 1, files)?;
                } else if kind.is_file() {
                    let bytes = std::fs::read(&path).map_err(|e| Error::io(&path, e))?;
                    files.insert(format!("{prefix}/{name}"), (content_type(&name), bytes));
                }
            }
            Ok(())
        }
        walk(dir, "", 0, &mut files)?;
        if !files.contains_key("/index.html") {
            return Err(Error::Argument(format!(
                "{}: no index.html (is it the built viewer, web/dist?)",
                dir.display()
            )));
        }
        Ok(Web {
            files,
            dir: Some(dir.to_path_buf()),
        })
    }
}

fn content_type(name: &str) -> &'static str {
    match name.rsplit('.').next().unwrap_or("") {
        "html" => "text/html; charset=utf-8",
        "js" | "mjs" => "text/javascript; charset=utf-8",
        "css" => "text/css; charset=utf-8",
        "json" | "map" => "application/json",
        "svg" => "image/svg+xml",
        "png" => "image/png",
        "ico" => "image/x-icon",
        "woff2" => "font/woff2",
        "woff" => "font/woff",
        "wasm" => "application/wasm",
        _ => "application/octet-stream",
    }
}

/// The CORS headers on every answer: any page may read it, with range requests (juicebox.js,
/// hic-straw ask for a .hic's bytes by range).
const CORS: [(header::HeaderName, &str); 4] = [
    (header::ACCESS_CONTROL_ALLOW_ORIGIN, "*"),
    (header::ACCESS_CONTROL_ALLOW_HEADERS, "Range, Content-Type"),
    (header::ACCESS_CONTROL_ALLOW_METHODS, "GET, HEAD, OPTIONS"),
    (
        header::ACCESS_CONTROL_EXPOSE_HEADERS,
        "Content-Length, Content-Range, Accept-Ranges",
    ),
];

/// Every request: the API under `/api/v1/`, served .hic files under `/files/`, the page else.
pub async fn handle(State(shared): State<Arc<Shared>>, request: Request) -> Response {
    let method = request.method().clone();
    let path = request.uri().path().to_string();
    let query = request.uri().query().unwrap_or("").to_string();
    let mut response = if method == Method::OPTIONS {
        empty(StatusCode::NO_CONTENT)
    } else if method != Method::GET && method != Method::HEAD {
        reply(Reply::error(405, "this server answers GET (and HEAD) only"))
    } else if path.len() + query.len() > MAX_QUERY_BYTES + 1024 {
        reply(Reply::error(400, "the request's URL is too long"))
    } else if path.starts_with("/api/") {
        let shared = shared.clone();
        match tokio::task::spawn_blocking(move || shared.api.respond(&path, &query)).await {
            Ok(answer) => reply(answer),
            Err(_) => reply(Reply::error(500, "the request's work failed")),
        }
    } else if let Some(name) = path.strip_prefix("/files/") {
        match shared.files.get(name) {
            Some(file) => {
                let (file, headers) = (file.clone(), request.headers().clone());
                tokio::task::spawn_blocking(move || serve_file(&file, &headers))
                    .await
                    .unwrap_or_else(|_| reply(Reply::error(500, "reading the file failed")))
            }
            None => reply(Reply::error(404, "no such file served")),
        }
    } else {
        let name = if path == "/" {
            "/index.html"
        } else {
            path.as_str()
        };
        match shared.web.files.get(name) {
            Some((kind, bytes)) => {
                let mut response = Response::new(Body::from(bytes.clone()));
                set(&mut response, header::CONTENT_TYPE, kind);
                response
            }
            None => reply(Reply::error(404, "not found")),
        }
    };
    for (name, value) in CORS {
        response
            .headers_mut()
            .insert(name, HeaderValue::from_static(value));
    }
    if method == Method::HEAD {
        *response.body_mut() = Body::empty();
    }
    response
}

fn set(response: &mut Response, name: header::HeaderName, value: &str) {
    if let Ok(value) = HeaderValue::from_str(value) {
        response.headers_mut().insert(name, value);
    }
}

fn empty(status: StatusCode) -> Response {
    let mut response = Response::new(Body::empty());
    *response.status_mut() = status;
    response
}

fn reply(answer: Reply) -> Response {
    let mut response = Response::new(Body::from(answer.body));
    *response.status_mut() =
        StatusCode::from_u16(answer.status).unwrap_or(StatusCode::INTERNAL_SERVER_ERROR);
    set(&mut response, header::CONTENT_TYPE, answer.content_type);
    response
}

/// A served file's bytes: the whole file (up to [`MAX_RANGE_BYTES`]) or the one range the
/// `Range` header asks for (`bytes=a-b`, `bytes=a-`, `bytes=-n`).
fn serve_file(path: &Path, headers: &HeaderMap) -> Response {
    let opened = std::fs::File::open(path).and_then(|f| f.metadata().map(|m| (f, m.len())));
    let Ok((mut file, size)) = opened else {
        return reply(Reply::error(500, "the file could not be read"));
    };
    let range = headers
        .get(header::RANGE)
        .map(|value| value.to_str().ok().and_then(|v| parse_range(v, size)));
    let (start, end, status) = match range {
        None => (0, size, StatusCode::OK),
        Some(Some((start, end))) => (start, end, StatusCode::PARTIAL_CONTENT),
        Some(None) => {
            let mut response = reply(Reply::error(
                416,
                &format!("the Range is not one range of bytes inside the file's {size}"),
            ));
            set(
                &mut response,
                header::CONTENT_RANGE,
                &format!("bytes */{size}"),
            );
            return response;
        }
    };
    if end - start > MAX_RANGE_BYTES {
        return reply(Reply::error(
            400,
            &format!("ask for at most {MAX_RANGE_BYTES} bytes at once (a Range header)"),
        ));
    }
    let mut bytes = vec![0u8; (end - start) as usize];
    if file.seek(SeekFrom::Start(start)).is_err() || file.read_exact(&mut bytes).is_err() {
        return reply(Reply::error(500, "the file could not be read"));
    }
    let mut response = Response::new(Body::from(bytes));
    *response.status_mut() = status;
    set(
        &mut response,
        header::CONTENT_TYPE,
        "application/octet-stream",
    );
    set(&mut response, header::ACCEPT_RANGES, "bytes");
    if status == StatusCode::PARTIAL_CONTENT {
        set(
            &mut response,
            header::CONTENT_RANGE,
            &format!("bytes {start}-{}/{size}", end - 1),
        );
    }
    response
}

/// One byte range `[start, end)` of a file of `size` bytes, from a `Range` header's value.
pub fn parse_range(value: &str, size: u64) -> Option<(u64, u64)> {
    let spec = value.trim().strip_prefix("bytes=")?;
    let (first, last) = spec.split_once('-')?;
    let number = |t: &str| {
        (!t.is_empty() && t.len() <= 19 && t.bytes().all(|b| b.is_ascii_digit()))
            .then(|| t.parse::<u64>().ok())
            .flatten()
    };
    let (start, end) = if first.is_empty() {
        let n = number(last)?.min(size);
        (size - n, size)
    } else {
        let start = number(first)?;
        let end = if last.is_empty() {
            size
        } else {
            number(last)?.checked_add(1)?.min(size)
        };
        (start, end)
    };
    (start < end).then_some((start, end))
}
