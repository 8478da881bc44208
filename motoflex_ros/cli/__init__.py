"""The ``motoflex`` command: one module per verb, each calling the pure core directly."""
