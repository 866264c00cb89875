//! What a riser deck reads into: [`RiserDeck`] with its `*SPRINGPRO` laws,
//! `*FLEXPROADD` records and `*FLEXJOINT` elements (laws resolved).

use std::collections::BTreeMap;

use super::Notice;
use crate::dynamics::KjointBuilder;
use crate::law::curve::Curve;
use crate::law::flex_joint::{FlexJointLaw, FlexProAdd};
use crate::law::KjointProperty;

/// A `*SPRINGPRO` record: a multilinear moment-angle law.
#[derive(Debug, Clone, PartialEq)]
pub struct SpringPro {
    /// `INDEX` of the law.
    pub index: u64,
    /// The `NPAIRS` (angle \[rad\], moment \[N·m\]) pairs as a curve.
    pub curve: Curve,
    /// Line of the record (1-based).
    pub line: usize,
}

/// A `*FLEXPROADD` record.
#[derive(Debug, Clone, PartialEq)]
pub struct FlexProAddRecord {
    /// `IMAT`: record id.
    pub id: u64,
    /// The validated settings.
    pub props: FlexProAdd,
    /// Line of the record (1-based).
    pub line: usize,
}

/// A `*FLEXJOINT` element with its resolved law.
#[derive(Debug, Clone, PartialEq)]
pub struct FlexJointElement {
    /// `NEL`: element id.
    pub id: u64,
    /// `JO`: origin node.
    pub origin_node: u64,
    /// `JE`: end node.
    pub end_node: u64,
    /// `IPRO`: bending (or classical) law index in `*SPRINGPRO` (0 = none).
    pub ipro: u64,
    /// `IMAT`: `*FLEXPROADD` record index (0 = none).
    pub imat: u64,
    /// `IPROT`: torsion law index in `*SPRINGPRO` (0 = none).
    pub iprot: u64,
    /// `LENGTH`: reference length \[m\] (read, unused).
    pub length: f64,
    /// The resolved and validated law.
    pub law: FlexJointLaw,
    /// Line of the record (1-based).
    pub line: usize,
}

impl FlexJointElement {
    /// The KJOINT2 joint of this element: a builder named `FLEXJOINT {NEL}` carrying the
    /// resolved law ([`KjointBuilder::flex_joint`]) on `property`, which must be a spherical
    /// joint (type 1; checked when the joint is inserted). The nodes `JO`, `JE` are the
    /// caller's to map onto bodies (body 1 = `JO`, body 2 = `JE`), and the joint's x axis must
    /// be the riser axis: give it with [`KjointBuilder::world_frame1`], or let the anchors define it.
    pub fn joint_builder(&self, property: KjointProperty) -> KjointBuilder {
        KjointBuilder::new(property)
            .name(format!("FLEXJOINT {}", self.id))
            .flex_joint(self.law.clone())
    }
}

/// The content of a riser deck.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RiserDeck {
    /// `*SPRINGPRO` laws by index.
    pub spring_laws: BTreeMap<u64, SpringPro>,
    /// `*FLEXPROADD` records by id.
    pub flex_props: BTreeMap<u64, FlexProAddRecord>,
    /// `*FLEXJOINT` elements, in file order.
    pub joints: Vec<FlexJointElement>,
    /// Notices (skipped keywords, ignored fields), in file order.
    pub notices: Vec<Notice>,
}
