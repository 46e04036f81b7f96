//! Wheel and rail profiles (stub, being written).
