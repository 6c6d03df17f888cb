"""The striker: its view of the ball (:mod:`.context`), its aim (:mod:`.targeting`), and the cards it plays."""
