pub mod riser;
