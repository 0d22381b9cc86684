//! `contactmap`: genome (Hi-C) and protein contact maps.
//!
//! The library is organised as the data flows:
//!
//! - [`io`] reads and writes files (`.cool` / `.mcool`, Juicer `.hic`, text tables and pairs) into
//!   the core types and back; readers stream sorted pixel blocks so that large maps never need to be
//!   held in memory;
//! - the core types: [`genome::BinTable`] (chromosomes cut into bins), [`matrix::ContactMatrix`]
//!   (upper-triangle sparse matrix with weight columns) and [`matrix::PixelBlock`];
//! - the tools several rooms share stand on the same ground floor, so that no room imports
//!   another only to borrow them: [`genome::View`] (cooltools' view frame), [`random`] (seeded
//!   streams and exact draws), [`geometry`] (cell lists);
//! - algorithms take core types and return core types or plain tables; they never open files:
//!   [`balance`] (ICE, VC, KR), [`expected`] (P(s), power laws), [`normalize`] (observed /
//!   expected), [`tads`] (insulation, directionality, TopDom, Armatus), [`score`] (calls against
//!   a truth), [`compartments`] (eigenvectors as cooltools, saddles), [`conformations`]
//!   (contact maps of 3D trajectories, as polychrom counts them);
//! - [`export`] writes files that carry computed results (a `.hic` with Juicer's normalisation
//!   vectors and expected values): it stands above both the formats and the algorithms;
//! - [`plot`] draws figures (heatmaps, P(s) curves, protein contact maps) as PNG or SVG;
//! - [`sim`] makes synthetic maps with a known truth (block-structured maps with TADs, polymer
//!   ensembles).
//!
//! The `contactmap` command line is a thin layer over these modules, in the binary (`src/cli/`):
//! each command parses its options into the library's parameters, calls the library and prints.
//! Modules import one another one way, the ground floor imports no room and no room borrows from
//! [`sim`], and no module imports from an ancestor's file (`tests/architecture.rs` checks it).
//!
//! Coordinates are 0-based and half-open; weights are multiplicative (cooler's convention).
//!
//! ```
//! use contactmap::genome::{BinTable, Chrom};
//! use contactmap::matrix::{CountType, MatrixBuilder};
//!
//! let bins = BinTable::fixed(vec![Chrom::new("chr1", 1_000), Chrom::new("chr2", 500)], 100)?;
//! let mut builder = MatrixBuilder::new(bins, CountType::Integer);
//! builder.push(0, 3, 2.0)?;
//! builder.push(3, 0, 1.0)?; // lower-triangle pixels are mirrored and summed
//! let matrix = builder.build();
//! assert_eq!(matrix.get(0, 3), 3.0);
//! let rows = matrix.bins().parse_region_bins("chr1:0-400")?;
//! assert_eq!(matrix.dense(rows.clone(), rows).sum(), 6.0);
//! # Ok::<(), contactmap::Error>(())
//! ```
//!
//! # The library by job
//!
//! Each section names the entry points of one job and shows them at work; every entry point
//! has its own example in its documentation. The examples read the fixtures under `data/`
//! (`data/README.md` says where they come from) and write only under the temporary folder.
//!
//! ## Open a matrix
//!
//! [`io::open_matrix`] recognises the file by its first bytes (`.cool`, `.mcool::/resolutions/N`,
//! HiCExplorer `.h5`, Juicer `.hic`, text tables and pairs with [`io::OpenOptions`]) and returns
//! a [`io::MatrixReader`]; [`io::cool::CoolReader::open`] and [`io::hic::HicReader::open`] open
//! one format directly. Protein inputs: [`io::structure::read_structure`] (PDB / mmCIF) and
//! [`io::predictions::read_prediction`] (RR, CCMpred matrices, trRosetta `.npz` ...).
//!
//! ```
//! use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
//!
//! let reader = open_matrix("data/CN.mm9.10000kb.cool", &OpenOptions::default())?;
//! assert_eq!(reader.bins().n_bins(), 278);
//! // cooler's number of pixels and sum of counts (data/reference/totals.tsv)
//! assert_eq!(reader.totals()?, (38_503, 499_864_755.0));
//! # Ok::<(), contactmap::Error>(())
//! ```
//!
//! ## Read pixels and weights
//!
//! [`io::MatrixReader::read_pixels`] streams the stored upper triangle of a rectangle of bins as
//! sorted [`PixelBlock`]s; [`io::MatrixReader::weights`] gives a weight column (always
//! multiplicative: divisive Juicer vectors are inverted on read). [`io::load_matrix`] reads a
//! whole map into a [`ContactMatrix`]; [`io::load_pixels`] gives the algorithms their
//! [`matrix::PixelSource`] (in memory when it fits a budget, streamed otherwise).
//!
//! ```
//! use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
//!
//! let uri = "data/cooler_test_file.mcool::/resolutions/100000";
//! let reader = open_matrix(uri, &OpenOptions::default())?;
//! let weights = reader.weights("weight")?; // cooler's ICE weights, stored by hic2cool
//! let n = reader.bins().n_bins();
//! let (mut raw, mut balanced) = (0.0, 0.0);
//! reader.read_pixels(0..n, 0..n, &mut |block| {
//!     for k in 0..block.len() {
//!         let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
//!         raw += block.count[k];
//!         let value = block.count[k] * weights.values[i] * weights.values[j];
//!         if value.is_finite() {
//!             balanced += value;
//!         }
//!     }
//!     Ok(())
//! })?;
//! assert_eq!(raw, 119_208_613.0); // cooler's sum of counts
//! assert!(balanced > 0.0 && balanced < raw);
//! # Ok::<(), contactmap::Error>(())
//! ```
//!
//! ## Balance
//!
//! [`balance::balance`] computes ICE as `cooler balance`, and VC, VC_SQRT, KR and SCALE as
//! Juicer ([`balance::BalanceParams`]: [`Default`] is cooler's, [`balance::BalanceParams::juicer`]
//! Juicer's), on the pixels of [`io::load_pixels_for_balancing`]. [`io::cool::store::store_weights`]
//! writes the weights into a cooler.
//!
//! ```
//! use contactmap::balance::{balance, BalanceParams};
//! use contactmap::io::{load_pixels_for_balancing, open_matrix, MatrixReader, OpenOptions};
//!
//! let reader = open_matrix("data/CN.mm9.10000kb.cool", &OpenOptions::default())?;
//! let pixels = load_pixels_for_balancing(&*reader, u64::MAX)?;
//! let ice = balance(&pixels, &BalanceParams::default())?;
//! assert!(ice.converged);
//! // the `weight` column cooler stored in the file, to cooler's tolerance
//! let stored = reader.weights("weight")?;
//! for (ours, cooler) in ice.weights.iter().zip(&stored.values) {
//!     assert_eq!(ours.is_nan(), cooler.is_nan());
//!     assert!(ours.is_nan() || (ours - cooler).abs() <= 1e-6 * cooler.abs());
//! }
//! # Ok::<(), contactmap::Error>(())
//! ```
//!
//! ## Expected (P(s))
//!
//! [`expected::expected_cis`] and [`expected::expected_trans`] are cooltools' `expected_cis` and
//! `expected_trans` tables over a [`genome::View`]; [`expected::cis_curves`] gives the
//! per-chromosome curves observed / expected needs; [`expected::logbin::logbin_expected`] the
//! log-binned P(s) and its slope; [`expected::powerlaw::power_law`] the power-law fits. Observed /
//! expected maps: [`normalize::Normalizer`] and [`normalize::NormalizedReader`].
//!
//! ```
//! use contactmap::expected::{expected_cis, CisParams};
//! use contactmap::genome::View;
//! use contactmap::io::{load_pixels, open_matrix, MatrixReader, OpenOptions};
//!
//! let reader = open_matrix("data/CN.mm9.10000kb.cool", &OpenOptions::default())?;
//! let pixels = load_pixels(&*reader, u64::MAX)?;
//! let view = View::chromosomes(reader.bins());
//! let table = expected_cis(&pixels, None, &view, &CisParams::default())?;
//! // cooltools' row chr1, dist 2 (data/reference/numerics/mm9_CN_10Mb.expected_cis.raw.tsv.gz)
//! assert_eq!((table.region_name(2), table.dist[2]), ("chr1", 2));
//! assert_eq!((table.n_total[2], table.count_sum[2]), (18, 1_114_921.0));
//! assert_eq!(table.count_avg[2], 1_114_921.0 / 18.0);
//! # Ok::<(), contactmap::Error>(())
//! ```
//!
//! ## TADs
//!
//! [`tads::call::call`] runs any caller ([`tads::call::Caller`]) over a view and returns
//! boundaries, domains and the caller's track; the callers themselves are
//! [`tads::insulation::insulation`] (cooltools' insulation score),
//! [`tads::directionality::directionality`] with [`tads::hmm::dixon_domains`] (Dixon's HMM),
//! [`tads::topdom::topdom`] and [`tads::armatus::armatus`] on the bands of
//! [`tads::band::cis_bands`].
//!
//! ```
//! use contactmap::genome::View;
//! use contactmap::genome::{BinTable, Chrom};
//! use contactmap::io::{load_pixels, InMemory};
//! use contactmap::matrix::{CountType, MatrixBuilder};
//! use contactmap::tads::call::{call, Caller};
//! use contactmap::tads::topdom::TopDomParams;
//!
//! // two 20-bin domains: dense inside, sparse between
//! let bins = BinTable::fixed(vec![Chrom::new("chr1", 40_000)], 1_000)?;
//! let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
//! for i in 0..40u64 {
//!     for j in i..40 {
//!         builder.push(i, j, if i / 20 == j / 20 { 50.0 } else { 1.0 })?;
//!     }
//! }
//! let matrix = InMemory::new("two domains".into(), builder.build());
//! let pixels = load_pixels(&matrix, u64::MAX)?;
//! let params = TopDomParams { statistical_filter: false, ..TopDomParams::default() };
//! let calls = call(&pixels, None, &View::chromosomes(&bins), &Caller::TopDom(params))?;
//! let boundaries: Vec<usize> = calls.boundaries.iter().map(|b| b.bin).collect();
//! assert_eq!(boundaries, [20]);
//! # Ok::<(), contactmap::Error>(())
//! ```
//!
//! ## Compartments
//!
//! [`compartments::eigs::eigs_cis`] and [`compartments::eigs::eigs_trans`] are cooltools'
//! `eigs_cis` and `eigs_trans` (oriented by a phasing track, [`compartments::eigs::Phasing`]);
//! [`compartments::saddle::digitize`], [`compartments::saddle::saddle_cis`],
//! [`compartments::saddle::saddle_trans`] and [`compartments::saddle::saddle_strength`] its
//! saddles.
//!
//! ```
//! use contactmap::compartments::cis::CisEigParams;
//! use contactmap::compartments::eigs::{eigs_cis, Phasing};
//! use contactmap::genome::{RegionSpec, View};
//! use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
//!
//! let uri = "data/cooler_test_file.mcool::/resolutions/100000";
//! let reader = open_matrix(uri, &OpenOptions::default())?;
//! let weights = reader.weights("weight")?.values;
//! let chr4 = RegionSpec { chrom: "chr4".into(), start_bp: 0, end_bp: 1_348_131, name: None };
//! let view = View::new(reader.bins(), &[chr4])?;
//! let eigs = eigs_cis(&*reader, &weights, &view, Phasing::default(), &CisEigParams::default())?;
//! // cooltools' eigenvalues of chr4 (data/reference/compartments/dm6_100kb.eigs_cis_phased.vals.tsv.gz)
//! let cooltools = [3.98262529, -3.012683741, -2.023304433];
//! for (ours, theirs) in eigs.eigs[0].values.iter().zip(cooltools) {
//!     assert!((ours - theirs).abs() < 1e-6 * theirs.abs(), "{ours} vs {theirs}");
//! }
//! # Ok::<(), contactmap::Error>(())
//! ```
//!
//! ## Write
//!
//! [`export::write_matrix`] writes a map in any format, named by the file's extension
//! ([`export::MatrixFormat`]) with what the formats take ([`export::MatrixOutput`]: the
//! resolutions of an `.mcool` or `.hic`, the assembly, a cooler's weight columns, a `.hic`'s
//! normalisations and compression): coolers (format-version 3, as cooler reads them; [`io::cool::write_cool`],
//! [`io::cool::write_mcool`]), pixel tables ([`io::text::write_text`]) and a Juicer `.hic` with
//! its normalisation vectors and expected values ([`export::write_hic`]). Each writes under a
//! temporary name and renames the file when it is complete.
//!
//! ```
//! use contactmap::export::{write_matrix, MatrixFormat, MatrixOutput};
//! use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
//!
//! let input = open_matrix("data/CN.mm9.10000kb.cool", &OpenOptions::default())?;
//! let path = std::env::temp_dir().join(format!("contactmap-lib-{}.cool", std::process::id()));
//! let format = MatrixFormat::from_extension(&path)?;
//! write_matrix(&*input, &path, format, &MatrixOutput::default())?;
//! let copy = open_matrix(path.to_str().unwrap(), &OpenOptions::default())?;
//! assert_eq!(copy.totals()?, input.totals()?);
//! assert_eq!(copy.weights("weight")?.values.len(), 278);
//! std::fs::remove_file(&path)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## Simulate
//!
//! [`sim::block_map`] draws a Hi-C-like map with known domains ([`sim::BlockMapParams`]);
//! [`sim::ensemble::run_ensemble`] runs Brownian-dynamics replicas of a bead-spring polymer
//! ([`sim::polymer::Polymer`], optional loop extrusion) and counts their contacts
//! ([`sim::gpu::run_ensemble_gpu`] does the same on a GPU).
//!
//! ```
//! use contactmap::sim::{block_map, BlockMapParams};
//!
//! let params = BlockMapParams { n_bins: 200, depth: 1e5, seed: 7, ..BlockMapParams::default() };
//! let map = block_map(&params)?;
//! // the true domains tile the chromosome, and a boundary starts every domain but the first
//! let top: Vec<_> = map.domains.iter().filter(|d| d.level == 0).collect();
//! assert_eq!((top[0].start_bin, top[top.len() - 1].end_bin), (0, 200));
//! assert!(top.windows(2).all(|w| w[0].end_bin == w[1].start_bin));
//! assert_eq!(map.boundaries.len(), top.len() - 1);
//! // Poisson counts around the asked depth
//! assert!((map.matrix.sum() - 1e5).abs() < 5.0 * 1e5f64.sqrt());
//! # Ok::<(), contactmap::Error>(())
//! ```
//!
//! ## Score
//!
//! [`score::boundaries::score_boundaries`] and [`score::boundaries::domain_overlap`] compare TAD
//! calls with a truth; [`score::contacts::score_contacts`] scores predicted residue contacts
//! against a structure ([`score::contacts::TrueContacts`]) as the CASP assessors do;
//! [`score::overlap::overlap`] compares two predictions; [`score::compartments::score_compartments`]
//! scores an eigenvector against known A/B types.
//!
//! ```
//! use contactmap::score::boundaries::score_boundaries;
//!
//! let truth = [("chr1".to_string(), 100_000), ("chr1".to_string(), 500_000)];
//! let calls = [("chr1".to_string(), 110_000), ("chr2".to_string(), 100_000)];
//! let score = score_boundaries(&truth, &calls, 10_000);
//! assert_eq!(score.true_positives, 1);
//! assert_eq!((score.precision, score.recall, score.f1), (0.5, 0.5, 0.5));
//! ```
//!
//! ## Plot
//!
//! [`plot::map::draw_map`] (heatmaps, square or 45-degree, with overlays and tracks),
//! [`plot::curves::draw_curves`] (P(s) and other curves), [`plot::protein::draw_contacts`]
//! (protein contact maps) and [`plot::saddle::draw_saddle`] build an [`plot::Svg`];
//! [`plot::figure_bytes`] turns it into the bytes of a PNG or SVG file.
//!
//! ```
//! use contactmap::plot::curves::{draw_curves, CurveFigure, Panel, Scale, Series};
//! use contactmap::plot::svg::Stroke;
//! use contactmap::plot::{figure_bytes, ImageFormat, Rgb};
//!
//! let series = Series {
//!     label: Some("s^-1".into()),
//!     points: (1..=100).map(|s| (s as f64 * 1e4, 1.0 / s as f64)).collect(),
//!     stroke: Stroke::solid(Rgb(31, 119, 180), 1.5),
//! };
//! let panel = Panel {
//!     y_label: "P(s)".into(),
//!     y_scale: Scale::Log,
//!     series: vec![series],
//!     weight: 1.0,
//!     legend: true,
//!     min_span: 0.0,
//! };
//! let figure = CurveFigure {
//!     title: String::new(),
//!     x_label: "distance".into(),
//!     x_scale: Scale::Log,
//!     x_in_bp: true,
//!     panels: vec![panel],
//!     width_px: 400,
//!     height_px: Some(300),
//!     dpi: 100.0,
//! };
//! let png = figure_bytes(&draw_curves(&figure)?, ImageFormat::Png, 100.0)?;
//! assert_eq!(&png[1..4], b"PNG");
//! // the IHDR chunk: width and height, big-endian
//! assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), 400);
//! assert_eq!(u32::from_be_bytes(png[20..24].try_into().unwrap()), 300);
//! # Ok::<(), contactmap::Error>(())
//! ```

pub mod balance;
pub mod compare;
pub mod compartments;
pub mod conformations;
pub mod diff;
pub mod error;
pub mod expected;
pub mod export;
pub mod genome;
pub mod geometry;
pub mod interrupt;
pub mod io;
pub mod loops;
pub mod matrix;
pub mod normalize;
pub mod numeric;
pub mod pairs;
pub mod pileup;
pub mod plot;
pub mod random;
pub mod score;
pub mod sim;
pub mod tads;
pub mod tiles;
pub mod validate;

pub use error::{Error, Result};
pub use genome::{Bin, BinTable, Chrom, Region};
pub use matrix::{ContactMatrix, CountType, MatrixBuilder, PixelBlock, Weights};
