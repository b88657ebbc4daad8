def read_fit(p): raise NotImplementedError
def score_record(t, r): raise NotImplementedError
