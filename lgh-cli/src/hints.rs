//! The command line's words for what the libraries say in their own terms: a library error
//! names its settings (`CubeMapSettings::memory_budget`), and the CLI, the one place that knows
//! the flags, adds the flags that change them (ARCHITECTURE.md, "Crates": lgh-cli is the only
//! place an error becomes a line of text).

use std::error::Error;

use lgh_volume::{ReadError, RenderError};

/// The flags that mend `e` (or an error in its chain of causes), where the library's message
/// names a setting the command line sets: printed on the error's line, after
/// `; on the command line: `.
pub(crate) fn flags(e: &(dyn Error + 'static)) -> Option<&'static str> {
    let mut next = Some(e);
    while let Some(e) = next {
        if let Some(hint) = e
            .downcast_ref::<RenderError>()
            .and_then(render)
            .or_else(|| e.downcast_ref::<ReadError>().and_then(read))
        {
            return Some(hint);
        }
        next = e.source();
    }
    None
}

/// A render error's flags.
fn render(e: &RenderError) -> Option<&'static str> {
    match e {
        RenderError::ShadowMemory { .. } => {
            Some("lower --alpha, raise --shadow-memory, or use --shadows raymarch")
        }
        RenderError::ScatterMemory { .. } => Some("lower --scatter-depth or raise --shadow-memory"),
        RenderError::Read(e) => read(e),
        _ => None,
    }
}

/// A read error's flags.
fn read(e: &ReadError) -> Option<&'static str> {
    match e {
        ReadError::FlameWithColour { .. } => Some("leave --flame-grid out (or give none)"),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An error that wraps another, as the commands' context does.
    #[derive(Debug)]
    struct Context(RenderError);

    impl std::fmt::Display for Context {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            write!(f, "frame 56: {}", self.0)
        }
    }

    impl Error for Context {
        fn source(&self) -> Option<&(dyn Error + 'static)> {
            Some(&self.0)
        }
    }

    #[test]
    fn the_flags_are_found_through_the_chain_of_causes() {
        let memory = RenderError::ShadowMemory {
            needed: 2 << 30,
            budget: 1 << 30,
            alpha: 2.0,
        };
        // The library names its setting, not the flag.
        assert!(memory
            .to_string()
            .contains("CubeMapSettings::memory_budget"));
        assert!(!memory.to_string().contains("--"));
        let hint = flags(&Context(memory)).unwrap();
        assert!(hint.contains("--shadow-memory") && hint.contains("--alpha"));
        let flame = RenderError::Read(ReadError::FlameWithColour {
            path: "rgb.vdb".into(),
            flame: "flame".into(),
            emission: "emission".into(),
        });
        assert!(!flame.to_string().contains("--"));
        assert!(flags(&flame).unwrap().contains("--flame-grid"));
        assert_eq!(flags(&RenderError::DensityOffGrid), None);
    }
}
