"""Flight code: a controller exported as a standalone C99 package (``rpo export``: :mod:`.emit`,
:mod:`.interface`, :mod:`.csource`, :mod:`.package`), the checks that make it flight code (:mod:`.checks`),
and a scenario flown with it in the loop (``rpo pil``: :mod:`.lockstep`, :mod:`.host`, :mod:`.pil`)."""
