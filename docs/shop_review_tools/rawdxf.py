import sys,collections
for fn in sys.argv[1:]:
    lines=open(fn).read().splitlines()
    pairs=[(lines[i].strip(),lines[i+1].strip()) for i in range(0,len(lines)-1,2)]
    c=collections.Counter(); ext={}; insec=None; th=[]; layers=collections.Counter()
    for i,(g,v) in enumerate(pairs):
        if g=='9' and v in('$ACADVER','$EXTMIN','$EXTMAX','$INSUNITS'):
            vals=[]; j=i+1
            while j<len(pairs) and pairs[j][0] not in('9','0'): vals.append(pairs[j][1][:9]); j+=1
            ext[v]=vals
        if g=='2' and i>0 and pairs[i-1]==('0','SECTION'): insec=v
        if g=='0' and v=='ENDSEC': insec=None
        if g=='0' and insec=='ENTITIES':
            c[v]+=1
            j=i+1
            while pairs[j][0]!='0':
                if pairs[j][0]=='8': layers[(v,pairs[j][1])]+=1
                if v in('TEXT','MTEXT') and pairs[j][0]=='40': th.append(float(pairs[j][1]))
                j+=1
    print(fn.split('/')[-3], fn.split('/')[-1], dict(c), ext, 'textH', sorted(set(th)), dict(layers))
