"""Flight-code checks of an exported controller package (``rpo export``): warnings, stack, MISRA, symbols."""
