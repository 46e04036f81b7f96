//! Wheel/rail contact (stub, being written).
