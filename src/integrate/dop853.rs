//! Dormand–Prince 8(5,3) (placeholder until implemented).
