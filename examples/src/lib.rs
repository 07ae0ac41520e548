//! Shared helpers of the course examples.
