"""What more than one concern of :mod:`scenarios` uses: file writers, figures, statistics, the batch engine."""
