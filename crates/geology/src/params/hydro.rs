//! `[hydro]`: flow through the network. No parameters yet: flows come from the sinks' weights.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HydroParams {}
