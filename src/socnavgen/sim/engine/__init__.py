"""The episode: the named state (state), one compiled step and the episode as a generator of steps (step),
the Simulation that builds the state and drives the generator (simulation), errors of trees while running
(errors), and a Simulation from a run folder (scenario)."""
