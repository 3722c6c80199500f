"""hardware layer of the Metamaterial Workbench."""
