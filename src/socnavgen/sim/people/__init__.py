"""The simulated people: their state and goal queues (state), their behavior trees lowered to one program
(trees) and interpreted (vm), one function per library leaf (leaves, give_way, leaves_hunav2), pacing at
the interaction point (pacing) and walking with the social force model, bodies kept apart (physics)."""
