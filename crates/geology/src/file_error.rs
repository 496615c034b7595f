//! The error of a data file the geological model reads (a potential grid, a lithology grid):
//! typed, naming the file and what is wrong in it (the field or value, the line or voxel), so
//! that the scene's validation reports it under the scene field that names the file.

/// A data file that cannot be read or whose content is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FileError {
    #[error("cannot read {file}: {reason}")]
    Read { file: String, reason: String },
    #[error("{file}: {problem}")]
    Content { file: String, problem: String },
}

impl FileError {
    /// `file` (a path as shown) cannot be read, because of `reason`.
    pub fn read(file: impl std::fmt::Display, reason: impl std::fmt::Display) -> Self {
        FileError::Read { file: file.to_string(), reason: reason.to_string() }
    }

    /// `file`'s content is wrong because of `problem`.
    pub fn content(file: impl std::fmt::Display, problem: impl std::fmt::Display) -> Self {
        FileError::Content { file: file.to_string(), problem: problem.to_string() }
    }
}
