//! Where a command's image goes: checks made before any work (the format, the folder), and the
//! rescue of a finished image whose write failed anyway.

use crate::cli_error::CliError;
use lancer::image_io::ImageFormat;
use std::path::{Path, PathBuf};

/// Refuses an output that cannot be written, before any rendering: unknown extension, missing
/// folder, or a folder where files cannot be created.
pub fn check_output(path: &Path) -> Result<(), CliError> {
    if ImageFormat::from_path(path).is_none() {
        return Err(CliError::input(format!(
            "{}: unknown image format (use .png or .exr)",
            path.display()
        )));
    }
    if path.is_dir() {
        return Err(CliError::input(format!(
            "{}: cannot write: it is a folder",
            path.display()
        )));
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !dir.is_dir() {
        return Err(CliError::input(format!(
            "{}: cannot write: folder {} does not exist",
            path.display(),
            dir.display()
        )));
    }
    let probe = dir.join(format!(".lancer-write-test-{}", std::process::id()));
    match std::fs::File::create(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(CliError::input(format!(
            "{}: cannot write in {}: {e}",
            path.display(),
            dir.display()
        ))),
    }
}

/// The default checkpoint path: the output's with `.ckpt` appended.
pub fn default_checkpoint_path(output: &Path) -> PathBuf {
    let mut p = output.as_os_str().to_os_string();
    p.push(".ckpt");
    PathBuf::from(p)
}

/// Writes the result with `write` to `output`; if that fails (a write error the checks before
/// rendering could not foresee), writes it into `fallback_dir` under a name of its own instead,
/// and reports both, so that hours of rendering are not lost to a full disk.
pub fn write_with_fallback(
    output: &Path,
    fallback_dir: &Path,
    write: impl Fn(&Path) -> Result<(), String>,
) -> Result<(), CliError> {
    let Err(first) = write(output) else {
        return Ok(());
    };
    let name = output
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "lancer.exr".into());
    let rescue = fallback_dir.join(format!("lancer-rescued-{}-{name}", std::process::id()));
    match write(&rescue) {
        Ok(()) => Err(CliError::runtime(format!(
            "{first}; the image was saved to {} instead",
            rescue.display()
        ))),
        Err(second) => Err(CliError::runtime(format!(
            "{first}; saving it to {} failed too: {second}",
            rescue.display()
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_falls_back_to_the_rescue_folder() {
        let dir = lancer_testing::ScratchDir::new("rescue");
        let out = Path::new("/no/such/folder/image.exr");
        let write =
            |p: &Path| std::fs::write(p, b"pixels").map_err(|e| format!("{}: {e}", p.display()));
        let e = write_with_fallback(out, &dir, write).unwrap_err();
        let rescued = dir.join(format!("lancer-rescued-{}-image.exr", std::process::id()));
        assert_eq!(std::fs::read(&rescued).unwrap(), b"pixels");
        let msg = e.message;
        assert!(msg.contains("/no/such/folder/image.exr"), "{msg}");
        assert!(msg.contains(&rescued.display().to_string()), "{msg}");
        // Both failing: the message says so, and names both places.
        let e = write_with_fallback(out, Path::new("/no/such/rescue"), write).unwrap_err();
        assert!(e.message.contains("failed too"), "{}", e.message);
        // A write that works goes to the output only.
        let ok = dir.join("ok.exr");
        write_with_fallback(&ok, &dir, write).unwrap();
        assert!(ok.exists());
    }

    #[test]
    fn the_checkpoint_sits_beside_the_output() {
        assert_eq!(
            default_checkpoint_path(Path::new("out/a.exr")),
            PathBuf::from("out/a.exr.ckpt")
        );
    }
}
