//! Storing a weight column into an existing cooler. Being written.
