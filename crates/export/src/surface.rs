//! The surface streams (streams.json) as the network formats see them: the category codes
//! VTK stores and the names CSV writes, for a node's role and a segment's motion. Water types
//! share the conduits' codes ([`WaterType::ALL`](karst_hydro::WaterType::ALL)), so one colour
//! table serves `network.vtp` and `streams.vtp`.

use karst_streams::{Motion, Role};

/// Node roles in code order.
pub const ROLES: [Role; 4] = [Role::Source, Role::Well, Role::Branch, Role::Pool];

/// Segment motions in code order.
pub const MOTIONS: [Motion; 3] = [Motion::Contact, Motion::FreeFall, Motion::Pool];

/// A role's name, as in streams.json.
pub fn role_name(role: Role) -> &'static str {
    match role {
        Role::Source => "source",
        Role::Well => "well",
        Role::Branch => "branch",
        Role::Pool => "pool",
    }
}

/// A motion's name, as in streams.json.
pub fn motion_name(motion: Motion) -> &'static str {
    match motion {
        Motion::Contact => "contact",
        Motion::FreeFall => "free_fall",
        Motion::Pool => "pool",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_the_artifact_s() {
        for role in ROLES {
            assert_eq!(serde_json::to_value(role).unwrap(), role_name(role));
        }
        for motion in MOTIONS {
            assert_eq!(serde_json::to_value(motion).unwrap(), motion_name(motion));
        }
    }
}
