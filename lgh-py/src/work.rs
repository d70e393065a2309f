//! Long work from Python: done in chunks with the GIL released (other Python threads run
//! meanwhile), and between chunks, with the GIL held again, Ctrl-C checked (a pending
//! `KeyboardInterrupt` stops the work and is raised) and the optional progress callback called
//! with `(done, total)` (an exception it raises stops the work too).

use pyo3::prelude::*;

/// Items a chunk: large enough that the release and the checks cost nothing measurable, small
/// enough that Ctrl-C answers within a fraction of a second (16,384 probes at α = 2 take about
/// 0.1 s on one core).
pub const CHUNK: usize = 16_384;

/// Runs `f(offset, inputs, outputs)` over matching chunks of `inputs` and `outputs` (as long)
/// with the GIL released, checking for signals and reporting to `progress` after each chunk.
pub fn chunked<I, O, F>(
    py: Python<'_>,
    inputs: &[I],
    outputs: &mut [O],
    progress: Option<&Bound<'_, PyAny>>,
    f: F,
) -> PyResult<()>
where
    I: Sync,
    O: Send,
    F: Fn(usize, &[I], &mut [O]) -> PyResult<()> + Sync,
{
    let total = inputs.len();
    debug_assert_eq!(total, outputs.len());
    for (k, (i, o)) in inputs
        .chunks(CHUNK)
        .zip(outputs.chunks_mut(CHUNK))
        .enumerate()
    {
        let offset = k * CHUNK;
        py.detach(|| f(offset, i, o))?;
        py.check_signals()?;
        if let Some(p) = progress {
            p.call1((offset + i.len(), total))?;
        }
    }
    Ok(())
}
