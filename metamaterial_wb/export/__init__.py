"""export layer of the Metamaterial Workbench."""
