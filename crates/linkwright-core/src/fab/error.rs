//! Why a design cannot be fabricated: [`FabError`], whose every message says what to change.

/// Why a design cannot be fabricated; every message says what to change.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FabError {
    /// The print settings cannot work (every issue, in words).
    #[error("print settings: {0}")]
    Settings(String),
    /// The model's scale has a zero term.
    #[error("the model's scale {0} has a zero term; both sides of a scale are whole numbers from 1")]
    Scale(crate::scene::Ratio),
    /// The design moves other bodies than the scene has (how, in words).
    #[error("the design does not match the scene: {0}")]
    Mismatch(String),
    #[error(
        "no room for the connector post of joint {joint} on {body}: the body is too thin for a post with \
         the print settings (make the body larger or connector_post smaller)"
    )]
    /// No place on a body is deep enough for a connector's post.
    NoRoomForPost {
        /// The joint the connector carries.
        joint: String,
        /// The body's name.
        body: String,
    },
    #[error(
        "no depth ordering of the links and connectors avoids every collision along the motion (paper \
         §7.2); choose another design (an alternative) or allow both faces with \"faces\": \"both\""
    )]
    /// No depth ordering satisfies every constraint recorded along the motion.
    NoOrdering,
    /// The depth-ordering solver used its whole step budget without finding an ordering or proving
    /// that none exists.
    #[error(
        "the depth-ordering solver gave up before finding an ordering of the links or proving that none \
         exists; choose another design (an alternative) or allow both faces with \"faces\": \"both\""
    )]
    OrderingTimedOut,
    #[error(
        "{body} is too thin for the connector post of joint {joint}, and every pad fused to its side near the \
         joint would enter another body (first at crank {at_deg:.1}°): draw the body thicker near the joint, \
         or choose another design"
    )]
    /// A body is too thin for a connector's post, and every pad that could carry it would enter
    /// another body along the motion.
    PadCollides {
        /// The joint the connector carries.
        joint: String,
        /// The body's name.
        body: String,
        /// The first crank angle where the pad would enter another body, degrees.
        at_deg: f64,
    },
    #[error(
        "joints {a} and {b} of {link} are closer than the {need_mm:.1} mm two pins need with these print settings: \
         the linkage is too small to print (choose a larger design, or narrower links and pins)"
    )]
    /// Two joints of a link are too close for two pins side by side.
    JointsTooClose {
        /// The link's name.
        link: String,
        /// One joint's name.
        a: String,
        /// The other joint's name.
        b: String,
        /// The least distance the print settings need between them, mm.
        need_mm: f64,
    },
    #[error(
        "{parts} fit the {width:.0} × {depth:.0} mm print area (the bed minus its margins) in no turn: print on a \
         bed of at least {square_bed_mm:.0} mm square (print settings \"bed\"), print a model at most \
         {max_scale:.2} times as large (the scene's build), or choose another design"
    )]
    /// Some links, connectors or the frame fit the print bed in no turn.
    OffBed {
        /// Their names, joined for the message.
        parts: String,
        /// The print area's width (the bed's minus its margins), mm.
        width: f64,
        /// The print area's depth, mm.
        depth: f64,
        /// The smallest square bed on which every one of them fits, mm.
        square_bed_mm: f64,
        /// The largest factor the scene could be scaled by for them to fit this bed.
        max_scale: f64,
    },
    /// A part's mesh could not be built, or a file encoded (why, in words).
    #[error("cannot build a part's solid: {0}")]
    Mesh(String),
    /// The linkage comes apart along the design's travel, or the travel is not usable (why).
    #[error("the design's motion cannot be simulated: {0}")]
    Motion(String),
    /// The design file is not valid against its scene ([`crate::DesignFile::validate`]).
    #[error("the design file is not valid: {}", joined_list(.0))]
    Invalid(crate::IssueList<crate::design::DesignIssue>),
    #[error(
        "the design fails its check against the scene ({}): fabricate a design that passes the check",
        joined(.0.iter().map(|v| format!("{}: {}", v.constraint, v.message)))
    )]
    /// The design fails its check against the scene ([`crate::DesignFile::violations`]).
    FailsCheck(Vec<crate::verify::Violation>),
    #[error("spring {spring}'s anchor on {part}: {}", hook_words(*.why))]
    /// A spring's anchor has no place for its hook.
    SpringHook {
        /// The spring, counted from 1.
        spring: usize,
        /// The part it is anchored on, as given.
        part: String,
        /// Why.
        why: HookRefusal,
    },
}

fn hook_words(why: HookRefusal) -> &'static str {
    match why {
        HookRefusal::NoSuchPart => "the design has no part of that name",
        HookRefusal::NotFinite => "the point is not a finite number",
        HookRefusal::BesideJoint => {
            "the point is on a link, too close to one of its joints for a hook beside the joint's pin \
             (hook it on the joint itself, or farther along the link)"
        }
        HookRefusal::NoRoom => "the body has no room for the post of a bracket reaching the point",
    }
}

/// Items of a message, one after the other.
fn joined<T: std::fmt::Display>(items: impl IntoIterator<Item = T>) -> String {
    items.into_iter().map(|i| i.to_string()).collect::<Vec<_>>().join("; ")
}

/// The listed problems joined, and how many more there are.
fn joined_list<T: std::fmt::Display>(list: &crate::IssueList<T>) -> String {
    match list.more() {
        0 => joined(list.iter()),
        more => format!("{}; and {more} more", joined(list.iter())),
    }
}

/// Why a spring's anchor has no hook.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HookRefusal {
    /// The design has no part of that name.
    NoSuchPart,
    /// The point is not a finite number.
    NotFinite,
    /// On a link, too close to one of its joints for a hook beside the joint's pin (and not on it).
    BesideJoint,
    /// No place on the body for the post of a bracket reaching the anchor.
    NoRoom,
}
