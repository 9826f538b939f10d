"""The run package's tour commands: generated homes and tours (``homesim generate``) and studies (``homesim study``)."""
