"""objects layer of the Metamaterial Workbench."""
