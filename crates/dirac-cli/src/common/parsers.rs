//! Clap value parsers (`value_parser = …`): what a bad value is refused with, before any work
//! is done (usage errors, exit code 2).

use std::convert::Infallible;
use std::path::PathBuf;

use clap::ValueEnum;
use dirac_cli::render::MAX_SIDE;

/// The command-line name of a value (`unit-area`, `real-block`, …).
pub fn value_name(value: &impl ValueEnum) -> String {
    value
        .to_possible_value()
        .map(|v| v.get_name().to_string())
        .unwrap_or_default()
}

/// A finite number.
pub fn finite(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("`{text}` is not a finite number")),
    }
}

/// A finite number greater than 0.
pub fn positive_real(text: &str) -> Result<f64, String> {
    let x = finite(text)?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err(format!("{x} is not positive"))
    }
}

/// A finite number, at least 0.
pub fn nonnegative_real(text: &str) -> Result<f64, String> {
    let x = finite(text)?;
    if x >= 0.0 {
        Ok(x)
    } else {
        Err(format!("{x} is negative"))
    }
}

/// An integer greater than 0.
pub fn positive_count(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(k) if k > 0 => Ok(k),
        _ => Err(format!("`{text}` is not a positive integer")),
    }
}

/// The former `--tau T`, refused with what replaced it.
pub fn replaced_tau(_: &str) -> Result<Infallible, String> {
    Err(
        "--tau was replaced by --operator family:T (or family-literal:T), e.g. \
         --operator family:0.5"
            .to_string(),
    )
}

/// `--size`: `WIDTHxHEIGHT`, both sides positive and at most [`MAX_SIDE`].
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let error = || format!("`{text}` is not a size WIDTHxHEIGHT in pixels (for example 800x600)");
    let (width, height) = text.split_once(['x', 'X']).ok_or_else(error)?;
    let side = |s: &str| s.trim().parse::<u32>().map_err(|_| error());
    let (width, height) = (side(width)?, side(height)?);
    if width == 0 || height == 0 {
        return Err(format!("size {text}: width and height must be positive"));
    }
    if width > MAX_SIDE || height > MAX_SIDE {
        return Err(format!(
            "size {text}: the largest side allowed is {MAX_SIDE} pixels"
        ));
    }
    Ok((width, height))
}

/// Output files with one of the given extensions (any case), so a wrong one is a usage error
/// before any work is done.
pub fn picture_path(
    extensions: &'static [&'static str],
) -> impl Fn(&str) -> Result<PathBuf, String> + Clone {
    move |text: &str| {
        let path = PathBuf::from(text);
        let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if extensions.iter().any(|e| e.eq_ignore_ascii_case(extension)) {
            Ok(path)
        } else {
            Err(format!(
                "{text}: the file name must end in .{}",
                extensions.join(" or .")
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_bad_ones_are_explained() {
        assert_eq!(parse_size("800x600"), Ok((800, 600)));
        assert_eq!(parse_size("64X48"), Ok((64, 48)));
        for bad in ["800", "800x", "x600", "-5x5", "axb", "800x600x2"] {
            let message = parse_size(bad).expect_err(bad);
            assert!(message.contains("WIDTHxHEIGHT"), "{bad}: {message}");
        }
        assert!(parse_size("0x10").expect_err("zero").contains("positive"));
        assert!(
            parse_size("99999x10")
                .expect_err("huge")
                .contains("largest")
        );
    }

    #[test]
    fn picture_paths_need_a_known_extension() {
        let parse = picture_path(&["png", "svg"]);
        assert_eq!(parse("a/b.SVG"), Ok(PathBuf::from("a/b.SVG")));
        assert!(
            parse("chart.gif")
                .expect_err("gif")
                .contains("chart.gif: the file name must end in .png or .svg")
        );
        assert!(parse("chart").is_err());
    }
}
