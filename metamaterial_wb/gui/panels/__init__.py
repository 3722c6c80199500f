"""Task panels, one per file."""
