//! Every HDF5 path, attribute name and code of the atlas file, in one place.
//!
//! ```text
//! /                       attrs: software, version, scene, scene_name, preset, accuracy,
//!                                integrator, command, created, run_time_s, x, y, along,
//!                                sweeps, overrides, masses, stops, dim, section_cap, [shard],
//!                                [parent, parent_labels_crc32, parent_box] (a zoom's),
//!                                attributes_crc32 (CRC-32 of the text attributes)
//! /axes/<x>, /axes/<y>    f64 [n]  coordinate vectors (attrs CLASS=DIMENSION_SCALE, NAME, start, stop,
//!                                  [lattice_start, lattice_stop, lattice_count] (layout 4))
//! /<x>, /<y>              f64 [n]  coordinate variables (dimension scales; attrs long_name, units, symbol),
//!                                  again in every sweep group and in /attractors
//! /<sweep>/               one group per sweep: fresh, up, down
//!     label_<mass>        u16 [ny, nx, 3]  (n, p, q); 65535 = S (sticking); n = 0 when not periodic
//!     class               u8  [ny, nx]     0 periodic, 1 chaotic, 2 unresolved, 3 quasiperiodic, 255 not computed
//!     flags               u8  [ny, nx]     bit k: stop k chatters; bit 4+k: stop k sticks (u32, bits k and 16+k, beyond 4 stops)
//!     symmetry            u8  [ny, nx]     0 none/not symmetric scene, 1 S, 2 AS
//!     lyapunov            f64 [ny, nx]     largest Lyapunov exponent per unit time (cells without a period; NaN otherwise)
//!     multiplier          f64 [ny, nx]     largest Floquet multiplier modulus (periodic cells; NaN otherwise)
//!     final_state         f64 [ny, nx, dim]
//!     periods, events     u64 [ny, nx]     work per cell
//!     reason              strings [reasons]  the distinct reasons of the sweep's unresolved cells (coordinate)
//!     reason_code         i32 [ny, nx]     why the cell is unresolved: index into reason; -1 resolved or not computed
//!     lines_done          u8  [lines]      1 where the line (row, or column with along=y) is computed
//!     entry_state         f64 [lines, dim] a zoom's up/down: the state each chain entered with (NaN: initial)
//!     sections/period/values   f64 [N, dim]      states at t = kT
//!     sections/<stop>/values   f64 [N, 1 + dim]  (phase t mod T, state just before impact)
//!     sections/<name>/offsets  u64 [ny*nx + 1]   CSR: cell i = iy*nx + ix owns rows offsets[i]..offsets[i+1]
//!     (per-cell datasets: chunks of whole lines, deflated; section values: uncompressed)
//! /hysteresis             u8  [ny, nx]     1 where up and down are periodic with different labels
//! /legend/<sweep>/<mass>/label   strings, most frequent first
//! /legend/<sweep>/<mass>/count   u64
//! (every string dataset: attribute text_crc32, the CRC-32 of its texts; every section values: data_crc32;
//! every dataset with values, from layout 3 on: values_crc32, the CRC-32 of its path and values)
//! ```

/// Version of this layout (root attribute `layout_version`; files without it
/// are version 1, read as well; newer versions are refused). Layout 3 (issue
/// 42) is layout 2 with `values_crc32` on every dataset with values. Layout
/// 4 is layout 3 with an axis on its parent's lattice (a zoom's: attributes
/// `lattice_start`, `lattice_stop`, `lattice_count`); a file without one is
/// written as layout 3.
pub const LAYOUT_VERSION: u64 = 4;
/// Dimension of the (n, p, q) counts of a label.
pub const NPQ: &str = "npq";
/// Dimension and coordinate of the state components (`x_M1`, …, `v_M1`, …).
pub const COMPONENT: &str = "component";
/// Dimension and coordinate of an impact section's columns (`phase`, then the state).
pub const IMPACT_COLUMN: &str = "impact_column";
/// Dimension and coordinate of the labelled masses.
pub const MASS: &str = "mass";
/// Dimension and coordinate of a sweep's label table.
pub const LABEL: &str = "label";
/// Dimension and coordinate of a sweep's table of reasons (why cells are unresolved).
pub const REASON: &str = "reason";
/// Per entry of the [`REASON`] table, the reason with its numbers as JSON
/// (the serialisation of `solver::Unresolved`: `kind` and the variant's
/// fields). Only in a sweep with unresolved cells; files written before
/// vibroatlas stored it (2026-11-29) have none, and their reasons read as
/// their texts.
pub const REASON_DETAIL: &str = "reason_detail";
/// Per cell, the index of its reason in the [`REASON`] table (-1: none).
pub const REASON_CODE: &str = "reason_code";
/// Colours of the label table.
pub const LABEL_COLOUR: &str = "label_colour";
/// Dimension of an RGB triple.
pub const RGB: &str = "rgb";
/// Dimension of the lines of a plane.
pub const LINE: &str = "line";
/// Dimension of the rows of a ragged section.
pub const POINT: &str = "point";
/// Dimension of a section's CSR offsets (cells + 1).
pub const CELL_EDGE: &str = "cell_edge";
/// Dimension of a legend's entries.
pub const ENTRY: &str = "entry";
/// Group of the coexisting attractors of an atlas (`atlas --attractors K`):
/// `count [y, x]`, `fraction [y, x, attractor]`, `label_code_<mass> [y, x,
/// attractor]` into its own `label` table, `section [y, x, attractor, point,
/// component]`, and their families: `family_id [y, x, attractor]`,
/// `family_fraction [family, y, x]`, `family_label_code_<mass> [family]`;
/// attributes `samples`, `seed`.
pub const ATTRACTORS: &str = "attractors";
/// Dimension of the attractor slots of a cell.
pub const ATTRACTOR: &str = "attractor";
/// Dimension of the attractor families of a plane.
pub const FAMILY_DIM: &str = "family";

/// Dataset of the label codes of a mass on each attractor family.
pub fn family_label_code(mass: &str) -> String {
    format!("family_label_code_{mass}")
}
/// Label text of a cell a shard did not compute.
pub const NOT_COMPUTED_LABEL: &str = "not-computed";
/// What the label coordinate holds.
pub const LABEL_COMMENT: &str = "n-p-q: period n in forcing periods, p and q impacts of the mass at its p-stop and q-stop over n periods (S: the mass sticks there, complete chattering); C chaotic, Q quasi-periodic, U unresolved";

/// Dataset of the label codes of a mass (index into the label table).
pub fn label_code(mass: &str) -> String {
    format!("label_code_{mass}")
}

/// Name of the software attribute value.
pub const SOFTWARE: &str = "vibroatlas";
/// Group of the axes.
pub const AXES: &str = "axes";
/// Group of the legends.
pub const LEGEND: &str = "legend";
/// Hysteresis mask dataset.
pub const HYSTERESIS: &str = "hysteresis";
/// Sections group inside a sweep group.
pub const SECTIONS: &str = "sections";
/// Period section name.
pub const PERIOD_SECTION: &str = "period";
/// Class code of a cell not computed (shards).
pub const NOT_COMPUTED: u8 = 255;
/// The codes of a cell's class, labels and symmetry (the journal's too).
pub use maps::code::{class_code, class_of, label_of, npq_code, symmetry_code, symmetry_of, STUCK};
/// Description of the class codes, stored as an attribute.
pub const CLASS_CODES: &str = "0 periodic, 1 chaotic, 2 unresolved, 3 quasiperiodic, 255 not computed";
/// Description of the symmetry codes.
pub const SYMMETRY_CODES: &str = "0 none, 1 S (symmetric), 2 AS (asymmetric)";

/// Dataset of mass labels in a sweep group.
pub fn label(mass: &str) -> String {
    format!("label_{mass}")
}

/// Description of the flag bits for `stops`.
pub fn flag_bits(stops: &[String]) -> String {
    let shift = if stops.len() <= 4 { 4 } else { 16 };
    stops
        .iter()
        .enumerate()
        .map(|(k, s)| format!("bit {k}: {s} chatters; bit {}: {s} sticks", k + shift))
        .collect::<Vec<_>>()
        .join("; ")
}

/// Bit shift of sticking flags for this many stops.
pub fn sticking_shift(stops: usize) -> u32 {
    if stops <= 4 {
        4
    } else {
        16
    }
}

/// The flags word of a cell: bit k when stop k chatters, bit
/// `k + sticking_shift` when it sticks.
pub fn flags_code(chatter: solver::Mask, sticking: solver::Mask, stops: usize) -> u32 {
    chatter.bits() | (sticking.bits() << sticking_shift(stops))
}

/// The chattering and sticking stops of a flags word.
pub fn flags_of(word: u32, stops: usize) -> (solver::Mask, solver::Mask) {
    let shift = sticking_shift(stops);
    (solver::Mask::from_bits(word & ((1 << shift) - 1)), solver::Mask::from_bits(word >> shift))
}

/// Names of curve files and of an atlas's `curves` group (`crate::curve`).
pub mod curves {
    /// The group of an atlas that holds its curves.
    pub const GROUP: &str = "curves";
    /// What the attribute `content` of a curve file (or group) says.
    pub const CONTENT: &str = "bifurcation curves";
    /// Attribute: what the file or group holds.
    pub const CONTENT_ATTR: &str = "content";
    /// Attribute of a curve: its kind (PD, SN, PF, NS, grazing).
    pub const KIND: &str = "kind";
    /// Attribute of a curve: why it ends.
    pub const ENDED: &str = "ended";
    /// Attribute of a curve: its free parameters, `A,B`.
    pub const FREE: &str = "free";
    /// Dimension of a curve's points.
    pub const POINT: &str = "point";
    /// Dimension of a curve's codimension-two points.
    pub const CODIM2: &str = "codim2";
    /// Dataset of the kinds of the codimension-two points.
    pub const CODIM2_KIND: &str = "codim2_kind";
    /// Attribute of the file or group: the CRC-32 of every curve as read
    /// (their number, and each one's kind, free parameters, end, points and
    /// codimension-two points, in order; `curve::values_crc32`).
    pub const CURVES_CRC32: &str = "curves_crc32";

    /// Group of the k-th curve.
    pub fn curve(k: usize) -> String {
        format!("curve_{k}")
    }

    /// Dataset of parameter `name` at the codimension-two points.
    pub fn codim2(name: &str) -> String {
        format!("codim2_{name}")
    }
}

/// Attribute names (root attributes of an atlas, of its axes and of the
/// attractors group), written and read by `write` and `read`.
pub mod attr {
    /// `software`.
    pub const SOFTWARE: &str = "software";
    /// `Conventions` (CF-1.8).
    pub const CONVENTIONS: &str = "Conventions";
    /// `created`.
    pub const CREATED: &str = "created";
    /// `sweeps`.
    pub const SWEEPS: &str = "sweeps";
    /// `stops`.
    pub const STOPS: &str = "stops";
    /// The normal of each stop's gap over the masses' positions, stops ×
    /// masses row by row (files written before it existed: derived from the
    /// stored scene when read).
    pub const STOP_NORMALS: &str = "stop_normals";
    /// The contact law of each stop, comma-separated names in stop order
    /// (`rigid`, `soft`; files written before it existed: derived from the
    /// stored scene when read).
    pub const STOP_LAWS: &str = "stop_laws";
    /// `state_masses`.
    pub const STATE_MASSES: &str = "state_masses";
    /// `start`.
    pub const START: &str = "start";
    /// `stop`.
    pub const STOP: &str = "stop";
    /// `shard`.
    pub const SHARD: &str = "shard";
    /// `lattice_start` of an axis (layout 4): the first value of the parent
    /// axis whose values a zoom's axis takes where they coincide.
    pub const LATTICE_START: &str = "lattice_start";
    /// `lattice_stop` of an axis (layout 4): the parent axis's last value.
    pub const LATTICE_STOP: &str = "lattice_stop";
    /// `lattice_count` of an axis (layout 4): the parent axis's values.
    pub const LATTICE_COUNT: &str = "lattice_count";
    /// `parent` of a zoom's root: the atlas it computed a box of, as given.
    pub const PARENT: &str = "parent";
    /// `parent_labels_crc32` of a zoom's root: the CRC-32 of the parent's
    /// labels (`store::labels_crc32`), 8 hexadecimal digits.
    pub const PARENT_LABELS_CRC32: &str = "parent_labels_crc32";
    /// `parent_box` of a zoom's root: the box's axes, `omega=A:B:N delta=C:D:M`.
    pub const PARENT_BOX: &str = "parent_box";
    /// `section_cap`.
    pub const SECTION_CAP: &str = "section_cap";
    /// `scene_name`.
    pub const SCENE_NAME: &str = "scene_name";
    /// `scene`.
    pub const SCENE: &str = "scene";
    /// `run_time_s`.
    pub const RUN_TIME_S: &str = "run_time_s";
    /// `q_stops`.
    pub const Q_STOPS: &str = "q_stops";
    /// `p_stops`.
    pub const P_STOPS: &str = "p_stops";
    /// `preset`.
    pub const PRESET: &str = "preset";
    /// `overrides`.
    pub const OVERRIDES: &str = "overrides";
    /// `masses`.
    pub const MASSES: &str = "masses";
    /// `quantities`: the names of the quantities of the steady motion each
    /// sweep stores, one `[y, x]` variable each (absent: none).
    pub const QUANTITIES: &str = "quantities";
    /// `reason_details`: the sweeps whose unresolved cells' reasons are
    /// stored with their numbers ([`super::REASON_DETAIL`]), comma-separated
    /// (absent: none, or a file before it). Covered by the root's
    /// `attributes_crc32`, it tells a detail deleted from a file from a
    /// file written before the details.
    pub const REASON_DETAILS: &str = "reason_details";
    /// `curves`: in an atlas that holds bifurcation curves in its `curves`
    /// group (`curves --into`), that group's `curves_crc32`, as decimal
    /// text. Covered by the root's `attributes_crc32`, it tells a deleted or
    /// replaced group from an atlas without curves (absent: none, or an
    /// atlas whose curves were stored before 2026-12-07).
    pub const CURVES: &str = "curves";
    /// `layout_version`.
    pub const LAYOUT_VERSION: &str = "layout_version";
    /// `integrator`.
    pub const INTEGRATOR: &str = "integrator";
    /// `history`.
    pub const HISTORY: &str = "history";
    /// `dim`.
    pub const DIM: &str = "dim";
    /// `command`.
    pub const COMMAND: &str = "command";
    /// `along`.
    pub const ALONG: &str = "along";
    /// `accuracy`.
    pub const ACCURACY: &str = "accuracy";
    /// `x`.
    pub const X: &str = "x";
    /// `y`.
    pub const Y: &str = "y";
    /// `symbol` of an axis coordinate: how figures write its parameter (`ω`).
    pub const SYMBOL: &str = "symbol";
    /// `long_name` (CF) of a variable; of an axis coordinate, what its
    /// parameter is (`forcing frequency`, or `parameter <name>`).
    pub const LONG_NAME: &str = "long_name";
    /// `units` (CF) of a variable.
    pub const UNITS: &str = "units";
    /// `flag_meanings` (CF) of a variable of codes: the meaning of each code
    /// of `flag_values`, separated by spaces (of a label code, its sweep's
    /// label table).
    pub const FLAG_MEANINGS: &str = "flag_meanings";
    /// `attractor_sampling` of the root (layout 3): `K samples per cell,
    /// seed S` when the atlas has an `/attractors` group, which a reader then
    /// requires (a text covered by the root's checksum, so the group cannot
    /// be deleted unseen).
    pub const ATTRACTOR_SAMPLING: &str = "attractor_sampling";
    /// `samples`.
    pub const SAMPLES: &str = "samples";
    /// `seed`.
    pub const SEED: &str = "seed";
    /// `text_crc32` of a dataset of texts (a string coordinate: `reason`,
    /// `label`, a legend's labels, …): the CRC-32 (zlib's) of its values, each
    /// its byte length (u64, little-endian) then its UTF-8 bytes, in order.
    /// HDF5 keeps texts in its global heap, which has no checksum; this
    /// attribute lives in the dataset's (checksummed) object header.
    pub const TEXT_CRC32: &str = "text_crc32";
    /// `data_crc32` of a dataset stored without compression (a section's
    /// `values`): the CRC-32 (zlib's) of all its values' bytes, in order,
    /// little-endian. Fletcher-32 of a chunk of zeros is 0, so a chunk
    /// zeroed with its checksum (a block a file system lost) passes the
    /// library's check; it does not pass this one.
    pub const DATA_CRC32: &str = "data_crc32";
    /// `values_crc32` of every dataset vibroatlas writes with values (issue
    /// 42): the CRC-32 (zlib's) of the dataset's path in the file (`/up/class`;
    /// its byte length, u64 little-endian, then its bytes), its values as
    /// stored (numbers: their bytes in order, little-endian; texts: each its
    /// byte length, u64 little-endian, then its bytes), and the file's run
    /// (u32 little-endian: the CRC-32 of the root's `created` and `command`
    /// texts, each its byte length, u64 little-endian, then its bytes). A value changed
    /// with its chunk's Fletcher-32 rewritten (h5py writes it), a dataset
    /// moved to another's path (`up` and `down` swapped), or one copied in
    /// from another run's file does not pass it. Written once the file has
    /// been read back.
    pub const VALUES_CRC32: &str = "values_crc32";
    /// `attributes_crc32` of an object (the root group, a coordinate, a
    /// curve's group): the CRC-32 of its scalar text attributes named in
    /// [`CHECKED_TEXTS`], in the byte
    /// order of their names, each its name's byte length (u64,
    /// little-endian), the name, its value's byte length and the value.
    pub const ATTRIBUTES_CRC32: &str = "attributes_crc32";
    /// The text attributes [`ATTRIBUTES_CRC32`] covers, those vibroatlas
    /// writes on the objects it seals (the root group, axis coordinates, a
    /// curve file's root and its curves' groups): any other text attribute,
    /// one a user adds with h5py for instance, is not checked, so that the
    /// file still reads.
    pub const CHECKED_TEXTS: &[&str] = &[
        "Conventions",
        "accuracy",
        "along",
        "attractor_sampling",
        "command",
        "content",
        "created",
        "curves",
        "ended",
        "free",
        "git_commit",
        "history",
        "integrator",
        "kind",
        "knobs",
        "long_name",
        "masses",
        "numbers_crc32",
        "overrides",
        "p_stops",
        "parent",
        "parent_box",
        "parent_labels_crc32",
        "preset",
        "q_stops",
        "quantities",
        "reason_details",
        "scene",
        "scene_name",
        "shard",
        "software",
        "source",
        "state_masses",
        "stop_laws",
        "stops",
        "sweeps",
        "symbol",
        "title",
        "units",
        "version",
        "x",
        "y",
    ];
    /// `numbers_crc32` of an object: the CRC-32 of its numeric attributes
    /// named in [`CHECKED_NUMBERS`], in the byte order of their names, each
    /// its name's byte length (u64, little-endian), the name, then its
    /// values as f64 (their count, u64 little-endian, then each value's
    /// bits, little-endian), written as 8 hexadecimal digits. A text
    /// attribute, so that [`ATTRIBUTES_CRC32`] covers it in turn: deleting it
    /// fails that check. Files written before it have none and read as
    /// before.
    pub const NUMBERS_CRC32: &str = "numbers_crc32";
    /// The numeric attributes [`NUMBERS_CRC32`] covers, those a reader takes
    /// content from: the state's dimension, the section cap, the stops'
    /// normals, an axis's ends and its lattice.
    pub const CHECKED_NUMBERS: &[&str] =
        &["dim", "lattice_count", "lattice_start", "lattice_stop", "section_cap", "start", "stop", "stop_normals"];
}

/// Dataset names inside a sweep group (and the sections and attractors groups).
pub mod var {
    /// `class`.
    pub const CLASS: &str = "class";
    /// `flags`.
    pub const FLAGS: &str = "flags";
    /// `symmetry`.
    pub const SYMMETRY: &str = "symmetry";
    /// `lyapunov` ([`maps::Number::Lyapunov`]'s name).
    pub const LYAPUNOV: &str = maps::Number::LYAPUNOV;
    /// `multiplier` ([`maps::Number::Multiplier`]'s name).
    pub const MULTIPLIER: &str = maps::Number::MULTIPLIER;
    /// `final_state`.
    pub const FINAL_STATE: &str = "final_state";
    /// `periods`.
    pub const PERIODS: &str = "periods";
    /// `events`.
    pub const EVENTS: &str = "events";
    /// `values`.
    pub const VALUES: &str = "values";
    /// `offsets`.
    pub const OFFSETS: &str = "offsets";
    /// `count`.
    pub const COUNT: &str = "count";
    /// `fraction`.
    pub const FRACTION: &str = "fraction";
    /// `section` of the attractors group: each attractor's first
    /// period-section points `[y, x, attractor, point, component]`.
    pub const SECTION: &str = "section";
    /// `family_id` of the attractors group: each attractor's family `[y, x, attractor]`.
    pub const FAMILY: &str = "family_id";
    /// `family_fraction`: each family's basin fraction `[family, y, x]`.
    pub const FAMILY_FRACTION: &str = "family_fraction";
    /// `lines_done`.
    pub const LINES_DONE: &str = "lines_done";
    /// `entry_state` of a zoom's continuation sweep: per line, the state its
    /// chain entered the plane with, from the parent (NaN: the scene's
    /// initial state).
    pub const ENTRY_STATE: &str = "entry_state";
}

#[cfg(test)]
mod tests {
    use super::*;
    use solver::{Class, Count, Label, Mask};

    /// Every kind of label comes back from its stored codes as it went in,
    /// counts beyond the code range are capped below `S`'s code.
    #[test]
    fn labels_round_trip_through_their_codes() {
        let labels = [
            Label::Periodic { n: 1, p: Count::Impacts(4), q: Count::Impacts(4) },
            Label::Periodic { n: 3, p: Count::Stuck, q: Count::Impacts(0) },
            Label::Periodic { n: 2, p: Count::Impacts(0), q: Count::Stuck },
            Label::Chaotic,
            Label::Quasiperiodic,
            Label::Unresolved,
        ];
        for l in labels {
            let code = class_code(l.class());
            assert_eq!(label_of(class_of(code).unwrap(), npq_code(l)), l, "{l}");
        }
        let many = Label::Periodic { n: 1, p: Count::Impacts(100_000), q: Count::Impacts(2) };
        assert_eq!(npq_code(many), [1, STUCK - 1, 2]);
        assert_eq!(class_of(NOT_COMPUTED), None);
    }

    /// Chattering and sticking stops share one flags word and come apart again,
    /// for the small (≤ 4 stops, 8 bits) and the wide layout.
    #[test]
    fn flags_round_trip_for_small_and_wide_scenes() {
        for stops in [1, 3, 4, 5, 16] {
            let chatter = Mask::of(stops, |k| k % 2 == 0);
            let sticking = Mask::of(stops, |k| k % 3 == 1);
            let word = flags_code(chatter, sticking, stops);
            assert_eq!(flags_of(word, stops), (chatter, sticking), "{stops} stops");
            if stops <= 4 {
                assert!(word < 256, "fits the u8 dataset");
            }
        }
        assert_eq!(class_of(class_code(Class::Quasiperiodic)), Some(Class::Quasiperiodic));
    }
}
