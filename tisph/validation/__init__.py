"""Reference data and exact solutions, each with its source."""
