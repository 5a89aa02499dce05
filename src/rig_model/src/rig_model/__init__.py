"""rig_model's Python side: the strict YAML reader the project's scripts share."""
