"""Studies: analyses built on the models (may use cases and estimation; models never import studies)."""
