//! The importer's one error type.

use std::fmt;

/// Why a glTF file could not be imported. Every variant names the file (`file`: the path
/// given to [`load`](crate::load), or [`SLICE_FILE`](crate::SLICE_FILE) for
/// [`load_slice`](crate::load_slice)), the object (its kind, glTF index and name, where it
/// has one) and the problem. Nothing in a file makes the importer panic.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Error {
    /// The file itself could not be read.
    Io {
        /// The file.
        file: String,
        /// The operating system's message.
        problem: String,
    },
    /// Not glTF 2.0: JSON that does not parse, or a `.glb` container that is truncated or
    /// malformed (header, chunk lengths).
    Parse {
        /// The file.
        file: String,
        /// What is wrong.
        problem: String,
    },
    /// The document breaks the glTF 2.0 schema at a JSON path (a reference past the end of
    /// its array, a missing required field, a value outside its enumeration).
    Invalid {
        /// The file.
        file: String,
        /// Where, as a JSON path (`meshes[0].primitives[1].indices`).
        path: String,
        /// What is wrong.
        problem: String,
    },
    /// `extensionsRequired` names an extension this importer does not implement (it
    /// implements [`SUPPORTED_EXTENSIONS`](crate::SUPPORTED_EXTENSIONS)).
    UnsupportedExtension {
        /// The file.
        file: String,
        /// The extension's name.
        extension: String,
    },
    /// A buffer could not be loaded: a missing or unreadable external file, a malformed
    /// data URI, a `.glb` BIN chunk that is absent, fewer bytes than its `byteLength`.
    Buffer {
        /// The file.
        file: String,
        /// The buffer's glTF index.
        buffer: usize,
        /// Its name, if it has one.
        name: Option<String>,
        /// What is wrong.
        problem: String,
    },
    /// An accessor (or its buffer view) reaches past its data, has a type its use does not
    /// allow, or holds a non-finite float.
    Accessor {
        /// The file.
        file: String,
        /// The accessor's glTF index.
        accessor: usize,
        /// Its name, if it has one.
        name: Option<String>,
        /// What is wrong.
        problem: String,
    },
    /// A mesh primitive is inconsistent: an index past its vertex count, attributes of
    /// different lengths.
    Primitive {
        /// The file.
        file: String,
        /// The mesh's glTF index.
        mesh: usize,
        /// The mesh's name, if it has one.
        name: Option<String>,
        /// The primitive's index in the mesh.
        primitive: usize,
        /// What is wrong.
        problem: String,
    },
    /// A node has a non-finite transform, or the hierarchy is not a forest (a cycle, a
    /// node with two parents).
    Node {
        /// The file.
        file: String,
        /// The node's glTF index.
        node: usize,
        /// Its name, if it has one.
        name: Option<String>,
        /// What is wrong.
        problem: String,
    },
    /// A material has a non-finite factor.
    Material {
        /// The file.
        file: String,
        /// The material's glTF index.
        material: usize,
        /// Its name, if it has one.
        name: Option<String>,
        /// What is wrong.
        problem: String,
    },
    /// An image could not be decoded (not PNG, JPEG or WebP, corrupt, over the size
    /// limits of [`LoadOptions`](crate::LoadOptions)).
    Image {
        /// The file.
        file: String,
        /// The image's glTF index.
        image: usize,
        /// Its name, if it has one.
        name: Option<String>,
        /// What is wrong.
        problem: String,
    },
    /// The scene as a whole breaks a limit of the renderer (`scene::Scene::validate`), e.g.
    /// transforms whose products overflow to infinity.
    Scene {
        /// The file.
        file: String,
        /// The renderer's message.
        problem: String,
    },
}

/// `kind index ("name")`.
fn object(
    f: &mut fmt::Formatter<'_>,
    kind: &str,
    index: usize,
    name: &Option<String>,
) -> fmt::Result {
    write!(f, "{kind} {index}")?;
    if let Some(n) = name {
        write!(f, " ({n:?})")?;
    }
    Ok(())
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Io { file, problem } => write!(f, "{file}: cannot read the file: {problem}"),
            Error::Parse { file, problem } => write!(f, "{file}: not glTF 2.0: {problem}"),
            Error::Invalid {
                file,
                path,
                problem,
            } => write!(f, "{file}: invalid glTF at {path}: {problem}"),
            Error::UnsupportedExtension { file, extension } => write!(
                f,
                "{file}: extensionsRequired names {extension:?}, which this importer does not \
                 implement (it implements {})",
                crate::SUPPORTED_EXTENSIONS.join(", ")
            ),
            Error::Buffer {
                file,
                buffer,
                name,
                problem,
            } => {
                write!(f, "{file}: ")?;
                object(f, "buffer", *buffer, name)?;
                write!(f, ": {problem}")
            }
            Error::Accessor {
                file,
                accessor,
                name,
                problem,
            } => {
                write!(f, "{file}: ")?;
                object(f, "accessor", *accessor, name)?;
                write!(f, ": {problem}")
            }
            Error::Primitive {
                file,
                mesh,
                name,
                primitive,
                problem,
            } => {
                write!(f, "{file}: ")?;
                object(f, "mesh", *mesh, name)?;
                write!(f, ", primitive {primitive}: {problem}")
            }
            Error::Node {
                file,
                node,
                name,
                problem,
            } => {
                write!(f, "{file}: ")?;
                object(f, "node", *node, name)?;
                write!(f, ": {problem}")
            }
            Error::Material {
                file,
                material,
                name,
                problem,
            } => {
                write!(f, "{file}: ")?;
                object(f, "material", *material, name)?;
                write!(f, ": {problem}")
            }
            Error::Image {
                file,
                image,
                name,
                problem,
            } => {
                write!(f, "{file}: ")?;
                object(f, "image", *image, name)?;
                write!(f, ": {problem}")
            }
            Error::Scene { file, problem } => {
                write!(
                    f,
                    "{file}: the imported scene breaks a renderer limit: {problem}"
                )
            }
        }
    }
}

impl std::error::Error for Error {}
