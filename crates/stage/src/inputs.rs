//! The upstream payloads a stage reads, as a tuple of payload types.

use std::path::Path;

use karst_artifact::{Frame, Header, Payload, StageId, check_frame, read_artifact};

use crate::handoff::Handoff;

/// A tuple of upstream payloads, read from an output folder.
pub trait Inputs: Sized {
    /// The stages that write them, in order.
    fn stages() -> Vec<StageId>;

    /// Reads each one from `dir`, checking it and that it is in the run's `frame`, and keeps
    /// its header (its payload hash goes into the key; its inputs are checked against the
    /// other inputs'). A payload the previous stage of the same run handed over
    /// ([`Handoff`]) is taken from memory when the file is still the one it was written to.
    fn read(
        dir: &Path,
        frame: &Frame,
        handoff: Option<&Handoff>,
        headers: &mut Vec<Header>,
    ) -> Result<Self, karst_artifact::Error>;
}

fn read_one<P: Payload + Clone + Send + 'static>(
    dir: &Path,
    frame: &Frame,
    handoff: Option<&Handoff>,
    headers: &mut Vec<Header>,
) -> Result<P, karst_artifact::Error> {
    let path = dir.join(P::STAGE.file_name());
    let (header, payload) = match handoff.and_then(|h| h.take::<P>(&path)) {
        Some(handed) => handed,
        None => read_artifact::<P>(&path)?,
    };
    check_frame(&path, &header, frame)?;
    headers.push(header);
    Ok(payload)
}

impl Inputs for () {
    fn stages() -> Vec<StageId> {
        Vec::new()
    }

    fn read(
        _: &Path,
        _: &Frame,
        _: Option<&Handoff>,
        _: &mut Vec<Header>,
    ) -> Result<Self, karst_artifact::Error> {
        Ok(())
    }
}

/// `impl Inputs for (A, B, …)`: reads each payload in turn.
macro_rules! tuple_inputs {
    ($($p:ident),+) => {
        impl<$($p: Payload + Clone + Send + 'static),+> Inputs for ($($p,)+) {
            fn stages() -> Vec<StageId> {
                vec![$($p::STAGE),+]
            }

            fn read(
                dir: &Path,
                frame: &Frame,
                handoff: Option<&Handoff>,
                headers: &mut Vec<Header>,
            ) -> Result<Self, karst_artifact::Error> {
                Ok(($(read_one::<$p>(dir, frame, handoff, headers)?,)+))
            }
        }
    };
}

tuple_inputs!(A);
tuple_inputs!(A, B);
tuple_inputs!(A, B, C);
tuple_inputs!(A, B, C, D);
tuple_inputs!(A, B, C, D, E);
tuple_inputs!(A, B, C, D, E, F);
