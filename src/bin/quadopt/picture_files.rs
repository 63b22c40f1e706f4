//! Picture files: the format from the name, the bytes rendered by [`picture`], the file
//! written by `quadopt::io`'s atomic output ([`quadopt::io::write_file`]) or to stdout.

use crate::fail::Fail;
use crate::picture;
use crate::stdout::{is_stdout, stdout_write_error};
use quadopt::io;
use std::path::Path;

/// A picture file's format, from its name.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum PictureFormat {
    Svg,
    Png,
}

impl PictureFormat {
    /// `.png` or `.svg` (any case); `-` (stdout) is SVG.
    pub fn of(path: &Path) -> Result<PictureFormat, Fail> {
        if is_stdout(path) {
            return Ok(PictureFormat::Svg);
        }
        match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("svg") => Ok(PictureFormat::Svg),
            Some("png") => Ok(PictureFormat::Png),
            _ => Err(Fail::Other(format!(
                "{}: not a picture file name (expected the extension .png or .svg, or - for SVG on stdout)",
                path.display()
            ))),
        }
    }
}

/// Writes `picture` to `path` (or stdout for `-`) in `format`.
pub fn write_picture(path: &Path, format: PictureFormat, picture: &picture::Picture) -> Result<(), Fail> {
    let bytes = match format {
        PictureFormat::Svg => picture::svg::render(picture).into_bytes(),
        PictureFormat::Png => {
            picture::png::render(picture).map_err(|e| Fail::Other(format!("{}: {e}", path.display())))?
        }
    };
    if is_stdout(path) {
        use std::io::Write as _;
        let mut out = std::io::stdout().lock();
        out.write_all(&bytes).and_then(|()| out.flush()).map_err(stdout_write_error)?;
    } else {
        io::write_file(path, &bytes)?;
    }
    Ok(())
}
