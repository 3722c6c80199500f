"""objects layer of the Metamaterial Workbench: FeaturePython document objects, one family per file
(``scene``, ``shapes``, ``item``, ``module``; placing a frame: ``display``; the make functions: ``make``).

Importing any of them watches documents and repairs those already open (``common.install_document_guard``):
proxies lost by a restore without the package are re-attached from their ``ProxyClass`` record.
"""
from metamaterial_wb.objects.common import install_document_guard

install_document_guard()
