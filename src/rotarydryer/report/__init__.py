"""Views: plots and drawings. Views never recompute physics beyond what they draw."""
