"""placeholder"""
def write_fretting_files(out_dir, problem, solution, summary, plots=False, missing=None):
    return []
