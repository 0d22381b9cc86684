//! `contactmap serve`: the files given, as a HiGlass tile server (higlass-server's API, tiles as
//! clodius 0.22.2 computes them) with the viewer page at `/`.

mod api;
mod http;
mod registry;

use std::collections::HashMap;
use std::net::{IpAddr, SocketAddr};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use axum::serve::ListenerExt;
use clap::Args;

use contactmap::error::{Error, Result};
use contactmap::io::parse_memory_size;

/// Arguments of `contactmap serve`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Serves each map given (.mcool: all its resolutions; .hic: all its resolutions and norms; .cool:
its one resolution) under a UID made from its file name (GM12878.hg19.mcool -> GM12878), and
tracks over it: BED (domains), BEDPE (dots), bedGraph, or a table's column (table.tsv::COLUMN,
by default the insulation / E1 / coverage column contactmap writes), with higlass-server's API,
so that the HiGlass front end works unchanged:
  /api/v1/tilesets/              the list (uuid, name, datatype, filetype, coordSystem)
  /api/v1/tileset_info/?d=UID    resolutions, transforms, chromosomes (as clodius)
  /api/v1/tiles/?d=UID.z.x.y[.transform]   256 x 256 tiles, base64 float16 / float32 (as clodius)
  /api/v1/chrom-sizes/?id=UID    the chromosomes as TSV
  /files/NAME.hic                a served .hic's bytes, with range requests (juicebox.js, hic-straw)
and the viewer page (HiGlass, built from web/ by `make web`) at /. Transforms: default (ICE's
`weight` where the map has it, else counts), weight, KR, VC, VC_SQRT, as higlass-server offers them.

Only the files named here are served: no request reaches the filesystem, and nothing is written.
The server listens on loopback (127.0.0.1) unless --bind says otherwise. Ctrl-C stops it.

Examples:
  contactmap serve sample.mcool          # then open http://127.0.0.1:8989/
  contactmap serve wt.mcool ko.mcool     # side by side, zoom locked
  contactmap serve s.mcool tads.bed dots.bedpe ins.tsv --port 9000
  contactmap serve s.mcool --bind 0.0.0.0   # reachable from other machines")]
pub struct ServeArgs {
    /// The maps to serve (.mcool, .cool, .hic) and BED tracks over them (.bed, .bed.gz).
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// The port (0: any free port, printed at start).
    #[arg(long, default_value_t = 8989)]
    pub port: u16,
    /// The address to listen on (loopback by default; another address serves the network).
    #[arg(long, default_value = "127.0.0.1", value_name = "ADDRESS")]
    pub bind: IpAddr,
    /// Open the viewer in the default browser.
    #[arg(long)]
    pub open: bool,
    /// Memory for computed tiles kept for the next request (e.g. 256M, 2G; 0 keeps none).
    #[arg(long, default_value = "256M", value_name = "SIZE")]
    pub tile_cache: String,
    /// The built viewer page (default: web/dist of the source tree contactmap was built in).
    #[arg(long, value_name = "DIR")]
    pub web: Option<PathBuf>,
}

/// Run `contactmap serve`.
pub fn run(args: &ServeArgs) -> Result<()> {
    let cache_bytes = parse_memory_size(&args.tile_cache)
        .map_err(|e| Error::Argument(format!("--tile-cache {}: {e}", args.tile_cache)))?;
    let web_dir = match &args.web {
        Some(dir) => Some(dir.clone()),
        None => {
            let built = Path::new(env!("CARGO_MANIFEST_DIR")).join("web/dist");
            built.join("index.html").is_file().then_some(built)
        }
    };
    let registry = registry::Registry::open(&args.files)?;
    let files: HashMap<String, PathBuf> = registry
        .entries
        .iter()
        .filter(|e| e.filetype == "hic")
        .map(|e| (format!("{}.hic", e.uid), e.path.clone()))
        .collect();
    let web = http::Web::load(web_dir.as_deref())?;
    let listener =
        std::net::TcpListener::bind(SocketAddr::new(args.bind, args.port)).map_err(|e| {
            Error::Argument(format!("cannot listen on {}:{}: {e}", args.bind, args.port))
        })?;
    let address = listener
        .local_addr()
        .map_err(|e| Error::Argument(format!("the listening socket: {e}")))?;
    listener
        .set_nonblocking(true)
        .map_err(|e| Error::Argument(format!("the listening socket: {e}")))?;
    let url = format!("http://{address}/");
    if !args.bind.is_loopback() {
        eprintln!(
            "contactmap serve: warning: listening on {}, not loopback: anyone who can reach this \
             machine can read the maps served",
            args.bind
        );
    }
    for entry in &registry.entries {
        eprintln!(
            "contactmap serve: {} <- {} ({})",
            entry.uid,
            entry.path.display(),
            entry.describe()
        );
    }
    if web.dir.is_none() {
        eprintln!(
            "contactmap serve: the viewer page is not built (make web); serving the API only"
        );
    }
    eprintln!("contactmap serve: {url}");
    if args.open {
        open_browser(&url);
    }
    let shared = Arc::new(http::Shared {
        api: api::Api {
            registry,
            cache: api::TileCache::new(cache_bytes as usize),
        },
        web,
        files,
    });
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .map_err(|e| Error::Argument(format!("the server's runtime: {e}")))?;
    runtime.block_on(async move {
        let listener = tokio::net::TcpListener::from_std(listener)
            .map_err(|e| Error::Argument(format!("the listening socket: {e}")))?;
        let app = axum::Router::new()
            .fallback(http::handle)
            .with_state(shared);
        // Tiles go out as soon as they are written: without TCP_NODELAY, Nagle's algorithm
        // holds an answer's second write until the client acknowledges the first, which a client
        // may delay 40 ms (seen on the zoom walk's first tile).
        let listener = listener.tap_io(|stream| {
            let _ = stream.set_nodelay(true);
        });
        axum::serve(listener, app)
            .with_graceful_shutdown(stopped())
            .await
            .map_err(|e| Error::Argument(format!("the server stopped: {e}")))
    })?;
    eprintln!("contactmap serve: stopped");
    Ok(())
}

/// Resolves on Ctrl-C or SIGTERM.
async fn stopped() {
    let interrupt = async {
        let _ = tokio::signal::ctrl_c().await;
    };
    #[cfg(unix)]
    let terminate = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut signal) => {
                signal.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    #[cfg(not(unix))]
    let terminate = std::future::pending::<()>();
    tokio::select! {
        () = interrupt => {},
        () = terminate => {},
    }
}

fn open_browser(url: &str) {
    let opener = if cfg!(target_os = "macos") {
        "open"
    } else {
        "xdg-open"
    };
    if std::process::Command::new(opener).arg(url).spawn().is_err() {
        eprintln!("contactmap serve: could not start {opener}; open {url} yourself");
    }
}
