//! Protein inputs: structures (PDB / mmCIF), contact predictions (CASP RR, CCMpred / PSICOV
//! matrices, `i j score` tables, trRosetta `.npz`, `.npy` maps), sequences (FASTA) and contact
//! frequency tables.

pub mod fasta;
pub mod frequencies;
pub mod npz;
pub mod predictions;
pub mod structure;
