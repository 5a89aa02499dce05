"""ar_bringup: evaluation of the AR pipeline against rig_sim's ground truth (see evaluation.py)."""
