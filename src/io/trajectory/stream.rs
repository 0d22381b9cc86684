//! The conformations of a list of trajectories, opened one after the other and each read when
//! asked for.

use std::path::Path;
use std::sync::Arc;

use super::format::TrajectoryFormat;
use super::frame::{Conformation, Frames};
use super::selection::AtomSelection;
use super::{dcd, models, polychrom, table, xtc, xyz};
use crate::error::{Error, Result};

/// The conformations of `inputs`, one after the other, each read when asked for: an iterator of
/// `Result<Conformation>` (the first error ends it).
pub struct Trajectories {
    inputs: std::collections::VecDeque<String>,
    current: Option<Box<dyn Iterator<Item = Result<Conformation>>>>,
    failed: bool,
    selection: Option<Arc<AtomSelection>>,
}

impl Trajectories {
    /// Keep only `selection`'s atoms of every frame (frames must have its atom count: an error
    /// names the first that has not). The DCD reader converts only those atoms' coordinates.
    pub fn select(mut self, selection: AtomSelection) -> Trajectories {
        self.selection = Some(Arc::new(selection));
        self
    }
}

/// Open the trajectories `inputs` (each a folder, a file or a polychrom URI; the format detected
/// by [`TrajectoryFormat::detect`]). Nothing but the inputs' listing is read before the first
/// conformation is asked for.
///
/// ```
/// use contactmap::io::trajectory::open_trajectories;
/// let dir = std::env::temp_dir().join(format!("traj-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("two.xyz");
/// std::fs::write(&path, "2\nframe 1\nC 0 0 0\nC 1 0 0\n2\nframe 2\nC 0 0 0\nC 0 2 0\n")?;
/// let frames: Vec<_> = open_trajectories(&[path.to_string_lossy().into_owned()])?
///     .collect::<Result<_, _>>()?;
/// assert_eq!(frames.len(), 2);
/// assert_eq!(frames[1].positions[1], [0.0, 2.0, 0.0]);
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn open_trajectories(inputs: &[String]) -> Result<Trajectories> {
    if inputs.is_empty() {
        return Err(Error::Argument("no trajectory given".into()));
    }
    for input in inputs {
        let path = Path::new(input.split("::").next().unwrap_or(input));
        // the system's own words, as the other readers give them ("No such file or directory")
        std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    }
    Ok(Trajectories {
        inputs: inputs.iter().cloned().collect(),
        current: None,
        failed: false,
        selection: None,
    })
}

type Conformations = Box<dyn Iterator<Item = Result<Conformation>>>;

fn open_one(input: &str, selection: Option<&Arc<AtomSelection>>) -> Result<Conformations> {
    let frames: Conformations = match TrajectoryFormat::detect(input)? {
        TrajectoryFormat::Dcd => {
            // the DCD reader selects while it converts
            let selection = selection.cloned();
            return Ok(Frames::boxed(
                dcd::DcdFrames::open(Path::new(input))?.selecting(selection),
            ));
        }
        TrajectoryFormat::Polychrom => Box::new(polychrom::PolychromBlocks::open(input)?),
        TrajectoryFormat::Table => Box::new(table::TableConformations::open(Path::new(input))?),
        TrajectoryFormat::Xyz => Frames::boxed(xyz::XyzFrames::open(Path::new(input))?),
        TrajectoryFormat::Xtc => Frames::boxed(xtc::XtcFrames::open(Path::new(input))?),
        TrajectoryFormat::Models => Box::new(models::ModelFrames::open(Path::new(input))?),
    };
    Ok(match selection {
        None => frames,
        Some(selection) => {
            let selection = Arc::clone(selection);
            Box::new(frames.map(move |frame| frame.and_then(|c| selection.apply(c))))
        }
    })
}

impl Iterator for Trajectories {
    type Item = Result<Conformation>;

    fn next(&mut self) -> Option<Result<Conformation>> {
        if self.failed {
            return None;
        }
        loop {
            if let Some(current) = &mut self.current {
                match current.next() {
                    Some(Ok(conformation)) => return Some(Ok(conformation)),
                    Some(Err(error)) => {
                        self.failed = true;
                        return Some(Err(error));
                    }
                    None => self.current = None,
                }
            }
            let input = self.inputs.pop_front()?;
            match open_one(&input, self.selection.as_ref()) {
                Ok(opened) => self.current = Some(opened),
                Err(error) => {
                    self.failed = true;
                    return Some(Err(error));
                }
            }
        }
    }
}
