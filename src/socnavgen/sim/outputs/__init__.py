"""What a simulation leaves besides its trace: metrics.json, the trajectory plot and the animation
(files.write_outputs), with labels that never overlap (labels)."""
