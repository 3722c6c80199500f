"""objects layer of the Metamaterial Workbench: FeaturePython document objects, one family per file
(``scene``, ``shapes``, ``item``, ``module``; placing a frame: ``display``; the make functions: ``make``).

Importing any of them watches documents and repairs those already open (``docguard.install``):
proxies lost by a restore without the package are re-attached from their ``ProxyClass`` record.
"""
from metamaterial_wb.objects import docguard

docguard.install()
