"""geometry layer of the Metamaterial Workbench."""
