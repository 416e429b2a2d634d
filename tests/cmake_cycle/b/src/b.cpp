int b_symbol() { return 0; }
