//! Radau IIA order 5.
