"""Flight code: a controller exported as a standalone C99 package (``rpo export``: :mod:`.emit`,
:mod:`.interface`, :mod:`.csource`, :mod:`.package`), the checks that make it flight code (:mod:`.checks`),
and a scenario flown with it in the loop (``rpo pil``: :mod:`.lockstep`, :mod:`.host`, :mod:`.pil`), on this
machine or on an emulated Cortex-M (:mod:`.build`, :mod:`.target`, the harness in ``firmware/``)."""
