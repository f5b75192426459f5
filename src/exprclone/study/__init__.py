"""The paper's user study (Table 1) as a tool: :mod:`.make` writes a study folder (:mod:`.folder`) of photo sets
cloned by every method under opaque names, :mod:`.app` serves it to participants who rate each result 1 to 5
(:mod:`.participants` keeps their answers), and :mod:`.results` averages the ratings per method and set."""
