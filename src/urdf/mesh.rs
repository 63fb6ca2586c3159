//! Mesh files a URDF names: where they are (`package://`, `file://`,
//! relative paths) and their vertices (STL binary and ASCII, OBJ, COLLADA
//! with its unit and node transforms, through `mesh-loader`).
//!
//! Only the file the URDF names is opened: an OBJ's material library and a
//! COLLADA's images are never read. A COLLADA file is held to the URDF
//! reader's XML limits first (size, nodes, depth; no DTD, so no entity
//! expansion). Errors ([`MeshError`]) name the file, for the caller to turn
//! into a warning about the link.

use super::limits::{self, Limits};
use std::path::{Path, PathBuf};

/// The largest mesh file read (bytes).
pub const MAX_MESH_BYTES: u64 = 256 << 20;
/// The most vertices taken from one mesh file.
pub const MAX_MESH_VERTICES: usize = 10_000_000;

/// Where `package://NAME/…` meshes are looked for, in this order: the
/// folders above the URDF (a folder named NAME, or one holding NAME), the
/// `--package-path` folders (each either a package itself or a folder of
/// packages), then those of `ROS_PACKAGE_PATH`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshPaths {
    /// The URDF's folder (relative mesh paths start here).
    pub urdf_dir: PathBuf,
    /// Package folders given by the user.
    pub package_paths: Vec<PathBuf>,
    /// Whether `ROS_PACKAGE_PATH` is searched too.
    pub ros_package_path: bool,
}

/// Every mesh file `robot` names (collision and visual shapes) that
/// `paths` resolves, each once: the files a command reading the URDF may
/// open, which none of its outputs may be.
pub fn mesh_files(robot: &super::Robot, paths: &MeshPaths) -> Vec<PathBuf> {
    let shapes = (robot.links.iter()).flat_map(|l| l.collisions.iter().chain(&l.visuals));
    let mut out: Vec<PathBuf> = shapes
        .filter_map(|s| match &s.geometry {
            super::Geometry::Mesh { filename, .. } => paths.resolve(filename).ok(),
            _ => None,
        })
        .collect();
    out.sort();
    out.dedup();
    out
}

impl MeshPaths {
    /// Meshes of the URDF at `urdf`, with extra package folders, and
    /// `ROS_PACKAGE_PATH`.
    pub fn for_urdf(urdf: &Path, package_paths: &[PathBuf]) -> Self {
        Self {
            urdf_dir: urdf.parent().map(Path::to_path_buf).unwrap_or_default(),
            package_paths: package_paths.to_vec(),
            ros_package_path: true,
        }
    }

    /// The file `filename` (as written in the URDF) names, if it is a
    /// regular file inside the URDF's folder or a package folder; the error
    /// says where it was looked for, what was found instead, or that the
    /// path leads outside those folders (a `..` that climbs out of the
    /// package or the URDF's folder, an absolute path elsewhere): such a
    /// file is not opened. Paths are compared as written, after `.` and
    /// `..` (symbolic links are followed as the system does).
    pub fn resolve(&self, filename: &str) -> Result<PathBuf, MeshError> {
        if let Some(rest) = filename.strip_prefix("package://") {
            return self.resolve_package(filename, rest);
        }
        let p = Path::new(filename.strip_prefix("file://").unwrap_or(filename));
        let p = if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.urdf_dir.join(p)
        };
        let at = absolute_lexical(&p);
        let inside = |root: &Path| match (&at, absolute_lexical(root)) {
            (Some(a), Some(r)) => a.starts_with(r),
            _ => false,
        };
        let urdf_root = self.urdf_root();
        let roots = self.package_roots();
        if !std::iter::once(&urdf_root).chain(&roots).any(|r| inside(r)) {
            return Err(MeshError::Outside {
                filename: filename.into(),
                path: p,
            });
        }
        regular_file(p)
    }

    /// The URDF's folder (`.` for a URDF named without one).
    fn urdf_root(&self) -> PathBuf {
        if self.urdf_dir.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            self.urdf_dir.clone()
        }
    }

    /// The package folders given and (when searched) those of
    /// `ROS_PACKAGE_PATH`.
    fn package_roots(&self) -> Vec<PathBuf> {
        let mut roots = self.package_paths.clone();
        if self.ros_package_path
            && let Some(v) = std::env::var_os("ROS_PACKAGE_PATH")
        {
            roots.extend(std::env::split_paths(&v));
        }
        roots
    }

    fn resolve_package(&self, filename: &str, rest: &str) -> Result<PathBuf, MeshError> {
        let (name, inner) = rest.split_once('/').unwrap_or((rest, ""));
        if Path::new(inner).is_absolute() || lexical(Path::new(inner)).is_none() {
            return Err(MeshError::Outside {
                filename: filename.into(),
                path: PathBuf::from(inner),
            });
        }
        let mut roots: Vec<PathBuf> = self.urdf_dir.ancestors().map(Path::to_path_buf).collect();
        roots.extend(self.package_roots());
        let mut not_a_file = None;
        for root in &roots {
            let is_pkg = root.file_name().is_some_and(|n| n == name);
            let candidates = [root.join(name).join(inner), root.join(inner)];
            for c in candidates.iter().take(if is_pkg { 2 } else { 1 }) {
                match regular_file(c.clone()) {
                    Ok(p) => return Ok(p),
                    Err(MeshError::NotFound(_)) => {}
                    Err(e) => not_a_file = not_a_file.or(Some(e)),
                }
            }
        }
        Err(not_a_file.unwrap_or_else(|| MeshError::PackageNotFound {
            package: name.to_string(),
            file: inner.to_string(),
        }))
    }
}

/// `p` made absolute (against the working folder), then [`lexical`].
fn absolute_lexical(p: &Path) -> Option<PathBuf> {
    lexical(&std::path::absolute(p).ok()?)
}

/// `p` with `.` dropped and each `..` taking off the component before it;
/// `None` when a `..` climbs above the start.
fn lexical(p: &Path) -> Option<PathBuf> {
    use std::path::Component;
    let mut out = PathBuf::new();
    let mut depth = 0usize;
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir if depth == 0 => return None,
            Component::ParentDir => {
                out.pop();
                depth -= 1;
            }
            Component::Normal(n) => {
                out.push(n);
                depth += 1;
            }
            other => out.push(other.as_os_str()),
        }
    }
    Some(out)
}

/// `p` if it is a regular file; else what it is (not there, a folder, a
/// FIFO, a device, …) or why it cannot be looked at.
fn regular_file(p: PathBuf) -> Result<PathBuf, MeshError> {
    match std::fs::metadata(&p) {
        Ok(m) if m.is_file() => Ok(p),
        Ok(m) => Err(MeshError::NotAFile {
            kind: file_kind(&m.file_type()),
            path: p,
        }),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err(MeshError::NotFound(p)),
        Err(source) => Err(MeshError::Io { path: p, source }),
    }
}

/// What a file that is not a regular file is.
fn file_kind(t: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() {
        "a folder"
    } else {
        "not a regular file"
    }
}

/// The vertices (m, the file's frame, COLLADA's unit and node transforms
/// applied) of the mesh file at `path`.
pub fn read_vertices(path: &Path) -> Result<Vec<[f64; 3]>, MeshError> {
    let name = path.display().to_string();
    let file = || path.to_path_buf();
    let bytes = crate::io::read_capped(path, MAX_MESH_BYTES).map_err(|e| match e {
        crate::io::Capped::Io(source) => MeshError::Io {
            path: file(),
            source,
        },
        crate::io::Capped::TooLarge(size) => MeshError::TooLarge { path: file(), size },
    })?;
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let loader = mesh_loader::Loader::default();
    let never = |p: &Path| -> std::io::Result<Vec<u8>> {
        Err(std::io::Error::other(format!(
            "{} is not read (only the mesh the URDF names is)",
            p.display()
        )))
    };
    let scene = match ext.as_str() {
        "stl" => loader.load_stl_from_slice(&binary_stl_unnamed(bytes), path),
        "obj" => loader.load_obj_from_slice_with_reader(&bytes, path, never),
        "dae" => {
            let text = std::str::from_utf8(&bytes).map_err(|_| MeshError::NotUtf8(file()))?;
            limits::check(text, &name, &Limits::default()).map_err(|e| MeshError::Xml {
                path: file(),
                source: Box::new(e),
            })?;
            loader.load_collada_from_slice(&bytes, path)
        }
        _ => return Err(MeshError::Format { path: file(), ext }),
    }
    .map_err(|source| MeshError::Load {
        path: file(),
        source,
    })?;
    vertices_of(&scene, path)
}

/// A binary STL whose 80-byte header begins with `solid` (CAD exporters
/// write their part's name there, e.g. Solo12's feet) reads as a broken
/// ASCII STL: when the file is exactly a binary STL's size (84 bytes and
/// 50 per triangle its header counts) that word is blanked so the binary
/// reader takes it. An ASCII file of that exact size would have to declare
/// a triangle count in the billions in its bytes 80–84.
fn binary_stl_unnamed(mut bytes: Vec<u8>) -> Vec<u8> {
    let count = (bytes.get(80..84)).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as u64);
    let binary_size = count.is_some_and(|n| 84 + 50 * n == bytes.len() as u64);
    if binary_size && bytes.starts_with(b"solid") {
        bytes[..5].fill(0);
    }
    bytes
}

/// Every vertex of `scene` (at most [`MAX_MESH_VERTICES`], each finite, at
/// least one).
fn vertices_of(scene: &mesh_loader::Scene, path: &Path) -> Result<Vec<[f64; 3]>, MeshError> {
    let file = || path.to_path_buf();
    let mut out = Vec::new();
    for m in &scene.meshes {
        if out.len() + m.vertices.len() > MAX_MESH_VERTICES {
            return Err(MeshError::TooManyVertices(file()));
        }
        for v in &m.vertices {
            let p = v.map(f64::from);
            if !p.iter().all(|x| x.is_finite()) {
                return Err(MeshError::NonFiniteVertex(file()));
            }
            out.push(p);
        }
    }
    if out.is_empty() {
        return Err(MeshError::NoVertices(file()));
    }
    Ok(out)
}

/// Why a mesh file could not be found or used.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MeshError {
    /// A relative or absolute mesh path that is not a file.
    #[error("no such file ({})", .0.display())]
    NotFound(PathBuf),
    /// A path that leads outside the URDF's folder and the package folders
    /// (not opened).
    #[error(
        "'{filename}' leads outside the URDF's folder and the package folders ({}): not read; a package folder that holds it allows it",
        path.display()
    )]
    Outside {
        /// The path as the URDF writes it.
        filename: String,
        /// Where it leads.
        path: PathBuf,
    },
    /// The path names something that is not a regular file.
    #[error("{} is {kind}, not a mesh file", path.display())]
    NotAFile {
        /// The path.
        path: PathBuf,
        /// What it is.
        kind: &'static str,
    },
    /// A `package://` mesh found nowhere.
    #[error(
        "'{package}/{file}' not found above the URDF, in the package folders given or in ROS_PACKAGE_PATH"
    )]
    PackageNotFound {
        /// The package.
        package: String,
        /// The file inside it.
        file: String,
    },
    /// The file could not be read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// A file beyond [`MAX_MESH_BYTES`].
    #[error("{}: {size} bytes, more than the {} MiB a mesh may have", path.display(), MAX_MESH_BYTES >> 20)]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its size (bytes).
        size: u64,
    },
    /// A COLLADA file that is not UTF-8.
    #[error("{}: not UTF-8", .0.display())]
    NotUtf8(PathBuf),
    /// A COLLADA file beyond the XML limits.
    #[error("{}: {source}", path.display())]
    Xml {
        /// The file.
        path: PathBuf,
        /// The limit it passes.
        #[source]
        source: Box<super::UrdfError>,
    },
    /// An extension that is not STL, OBJ or DAE.
    #[error("{}: unknown mesh format '.{ext}' (STL, OBJ, DAE)", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// Its extension.
        ext: String,
    },
    /// The mesh loader could not read the file.
    #[error("{}: {source}", path.display())]
    Load {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// More than [`MAX_MESH_VERTICES`] vertices.
    #[error("{}: more than {MAX_MESH_VERTICES} vertices", .0.display())]
    TooManyVertices(PathBuf),
    /// A vertex that is not finite.
    #[error("{}: a vertex is not finite", .0.display())]
    NonFiniteVertex(PathBuf),
    /// No vertex at all.
    #[error("{}: no vertices", .0.display())]
    NoVertices(PathBuf),
}
